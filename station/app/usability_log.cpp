#include "station/app/usability_log.h"

#include <cinttypes>
#include <cmath>

namespace hd::station {

void UsabilityLog::poll(StationFrame& frame, const std::vector<std::string>& names) {
  CameraUsabilityEvent e;
  while (frame.pop_usability_event(e)) {
    const auto c = static_cast<std::size_t>(e.camera);
    if (c >= intervals_.size()) continue;
    const double t_s = 1e-9 * static_cast<double>(e.display_ns - start_ns_);
    std::fprintf(out_, "%s\n",
                 line(c < names.size() ? names[c] : "#" + std::to_string(c), e, t_s).c_str());
    std::fflush(out_);
    std::vector<UnusableInterval>& list = intervals_[c];
    if (!e.usable) {
      UnusableInterval u;
      u.from_s = t_s;
      u.from_frame = e.frame;
      u.age_at_start_ms = 1e3 * e.video_age_s;
      u.state = std::string(drivers::to_string(e.state));
      list.push_back(u);
    } else if (!list.empty() && list.back().to_s < 0.0) {
      list.back().to_s = t_s;
      list.back().to_frame = e.frame;
      list.back().first_new_frame_ns = e.first_new_frame_ns;
      list.back().to_display_ns = e.display_ns;
    }
  }
}

std::string UsabilityLog::line(const std::string& camera, const CameraUsabilityEvent& e,
                               double t_s) {
  char buf[256];
  char age[48];
  if (std::isnan(e.video_age_s))
    std::snprintf(age, sizeof age, "no frame yet");
  else
    std::snprintf(age, sizeof age, "video %.0f ms old", 1e3 * e.video_age_s);
  if (e.usable) {
    std::snprintf(buf, sizeof buf,
                  "  event    %+.3f s camera %s: usable from frame %" PRIu64 " (%s)", t_s,
                  camera.c_str(), e.frame, age);
  } else {
    std::snprintf(buf, sizeof buf,
                  "  event    %+.3f s camera %s: unusable from frame %" PRIu64
                  " (%s, %s): not shown as live video",
                  t_s, camera.c_str(), e.frame, age,
                  std::string(drivers::to_string(e.state)).c_str());
  }
  return buf;
}

}  // namespace hd::station
