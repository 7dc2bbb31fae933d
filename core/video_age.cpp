#include "core/video_age.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hd::core {

double default_max_video_age_s(double rate_hz, double known_delay_s) {
  const double periods = std::isfinite(rate_hz) && rate_hz > 0.0 ? 3.0 / rate_hz : 0.0;
  const double delay = std::isfinite(known_delay_s) && known_delay_s > 0.0 ? known_delay_s : 0.0;
  return std::max(0.1, periods) + delay;
}

double video_age_fade_s(double max_age_s, double time_constant_s) {
  if (!(time_constant_s > 0.0) || !(max_age_s > 0.0)) return 0.0;
  return std::min(time_constant_s, 0.5 * max_age_s);
}

double time_extended_m(double m, bool streaming, double age_s, double max_age_s) {
  if (std::isnan(m)) return m;
  // A frame stamped a little after the display time (clock noise, a device clock mapped ahead)
  // is fresh, not unknown: only NaN is unknown.
  const bool fresh = !std::isnan(age_s) && age_s < max_age_s;
  return streaming && fresh ? m : std::numeric_limits<double>::infinity();
}

double video_weight_cap(double age_s, double max_age_s, double fade_s) {
  if (std::isnan(age_s)) return 0.0;
  if (age_s <= max_age_s) return 1.0;
  if (!(fade_s > 0.0)) return 0.0;
  return std::clamp(1.0 - (age_s - max_age_s) / fade_s, 0.0, 1.0);
}

}  // namespace hd::core
