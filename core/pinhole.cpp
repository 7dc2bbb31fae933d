#include "core/pinhole.h"

#include <cmath>

namespace hd::core {

bool Pinhole::valid() const {
  return std::isfinite(fx) && std::isfinite(fy) && std::isfinite(cx) && std::isfinite(cy) &&
         fx > 0.0 && fy > 0.0 && width > 0 && height > 0;
}

}  // namespace hd::core
