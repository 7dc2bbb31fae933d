#include "core/marking.h"

#include <algorithm>
#include <cmath>

namespace hd::core {

MarkingParams MarkingParams::sanitized() const {
  const MarkingParams def;
  MarkingParams out = *this;
  out.frame_width_px = std::clamp(frame_width_px, 0, 4096);
  out.checker_cell_px = std::clamp(checker_cell_px, 1, 4096);
  out.synthetic_desaturation = std::isnan(synthetic_desaturation)
                                   ? def.synthetic_desaturation
                                   : std::clamp(synthetic_desaturation, 0.0, 1.0);
  out.checker_contrast =
      std::isnan(checker_contrast) ? def.checker_contrast : std::clamp(checker_contrast, 0.0, 1.0);
  return out;
}

}  // namespace hd::core
