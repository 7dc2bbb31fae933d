#include "station/selection/camera_need.h"

#include <cmath>
#include <limits>

namespace hd::station {

CameraNeedPolicy::CameraNeedPolicy(std::size_t cameras, CameraNeedParams params)
    : params_(params),
      last_wanted_ns_(cameras, 0),
      needed_(cameras, 1),
      kept_(cameras, 0),
      camera_changes_(cameras, 0) {}

void CameraNeedPolicy::update(std::span<const double> m, int chosen, int64_t now_ns) {
  if (!started_) {  // every camera counts as wanted just now: the hold starts at the first frame
    started_ = true;
    for (int64_t& t : last_wanted_ns_) t = now_ns;
  }
  int runner_up = -1;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.size() && i < needed_.size(); ++i)
    if (int(i) != chosen && std::isfinite(m[i]) && m[i] < best) {
      best = m[i];
      runner_up = int(i);
    }
  const int64_t hold_ns = static_cast<int64_t>(params_.hold_s * 1e9);
  for (std::size_t i = 0; i < needed_.size(); ++i) {
    const double mi = i < m.size() ? m[i] : std::numeric_limits<double>::quiet_NaN();
    const bool wanted = kept_[i] != 0 || int(i) == chosen || int(i) == runner_up ||
                        (std::isfinite(mi) && mi < params_.m_t + params_.margin);
    if (wanted) last_wanted_ns_[i] = now_ns;
    const uint8_t need = now_ns - last_wanted_ns_[i] < hold_ns || wanted ? 1 : 0;
    if (need != needed_[i]) {
      ++changes_;
      ++camera_changes_[i];
    }
    needed_[i] = need;
  }
}

}  // namespace hd::station
