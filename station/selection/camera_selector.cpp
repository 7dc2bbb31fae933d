#include "station/selection/camera_selector.h"

#include <cmath>

namespace hd::station {

int CameraSelector::update(std::span<const double> m, double dt_s) {
  int best = -1;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (!std::isfinite(m[i])) continue;
    if (best < 0 || m[i] < m[static_cast<std::size_t>(best)]) best = static_cast<int>(i);
  }
  const bool current_usable = current_ >= 0 && static_cast<std::size_t>(current_) < m.size() &&
                              std::isfinite(m[static_cast<std::size_t>(current_)]);
  if (!current_usable) {
    if (best != current_ && best >= 0) ++switches_;
    current_ = best;
    better_for_s_ = 0.0;
    return current_;
  }
  const double m_cur = m[static_cast<std::size_t>(current_)];
  if (best != current_ && m[static_cast<std::size_t>(best)] < (1.0 - params_.margin) * m_cur) {
    better_for_s_ += std::isfinite(dt_s) && dt_s > 0.0 ? dt_s : 0.0;
    if (better_for_s_ >= params_.dwell_s) {
      current_ = best;
      better_for_s_ = 0.0;
      ++switches_;
    }
  } else {
    better_for_s_ = 0.0;
  }
  return current_;
}

}  // namespace hd::station
