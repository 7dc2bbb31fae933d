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
  out.synthetic_fade = std::isnan(synthetic_fade) ? 0.0 : std::clamp(synthetic_fade, 0.0, 1.0);
  return out;
}

MarkingParams MarkingParams::for_ages(double model_age_ms, bool stale_video) const {
  MarkingParams out = *this;
  if (style == MarkingStyle::kNone) return out;
  out.video_stale = stale_video;
  if (std::isnan(model_age_ms) || !(model_age_ms > model_age_fresh_ms)) return out;
  const double span = model_age_full_ms - model_age_fresh_ms;
  const double s =
      span > 0.0 ? std::clamp((model_age_ms - model_age_fresh_ms) / span, 0.0, 1.0) : 1.0;
  out.synthetic_fade = std::clamp(stale_fade_max, 0.0, 1.0) * s;
  if (style == MarkingStyle::kChecker && stale_checker_contrast > checker_contrast)
    out.checker_contrast = checker_contrast + (stale_checker_contrast - checker_contrast) * s;
  return out;
}

}  // namespace hd::core
