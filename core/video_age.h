#pragma once
// Time as an input of the decision (the paper's "additional consideration of time"): how old a
// camera's newest frame may be at the predicted display time and still be shown as video, and
// how fast a frame that grew too old leaves the screen. Rule and reasoning: docs/truth.md.

#include <cstdint>

namespace hd::core {

/// The default bound on a camera's video age: three frame periods (a frame, one lost frame, and
/// the next one on its way), but at least 100 ms, plus any delay the camera is known to add
/// (e.g. a simulated network). rate_hz <= 0 or not finite (unknown): 100 ms plus the delay.
double default_max_video_age_s(double rate_hz, double known_delay_s = 0.0);

/// The age fade: after a camera becomes unusable its last frame may stay on screen (fading out
/// with the transition) for at most this long: min(time_constant_s, max_age_s / 2), 0 for a
/// transition without smoothing. So no video older than 1.5 max_age_s is ever shown.
double video_age_fade_s(double max_age_s, double time_constant_s);

/// m extended by time: m itself while the camera is usable -- its source is streaming and its
/// newest frame is younger than max_age_s at the display time (age_s >= 0 and finite) -- and
/// +inf otherwise, whatever its geometry. NaN m stays NaN (the transition treats it as +inf).
double time_extended_m(double m, bool streaming, double age_s, double max_age_s);

/// The highest video weight a frame of this age may be drawn with: 1 while age_s <= max_age_s,
/// falling linearly to 0 at max_age_s + fade_s (a step at max_age_s when fade_s <= 0). An
/// unknown age (NaN, or negative beyond clock noise) gives 0.
double video_weight_cap(double age_s, double max_age_s, double fade_s);

/// Age in seconds of something stamped at `stamp_ns` seen at `at_ns` (both CLOCK_MONOTONIC);
/// NaN when there is no stamp (0).
inline double age_s(int64_t stamp_ns, int64_t at_ns) {
  if (stamp_ns == 0) return __builtin_nan("");
  return 1e-9 * static_cast<double>(at_ns - stamp_ns);
}

}  // namespace hd::core
