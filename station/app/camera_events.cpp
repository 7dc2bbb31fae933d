#include "station/app/camera_events.h"

namespace hd::station {

void CameraEventLog::poll(const std::vector<drivers::CameraSource*>& cameras,
                          const std::vector<std::string>& names) {
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    drivers::FormatEvent e;
    while (cameras[i]->pop_format_event(e)) {
      CameraEventRecord r;
      r.camera = i < names.size() ? names[i] : cameras[i]->id();
      r.kind = e.kind == drivers::FormatEventKind::kLost ? "format_lost" : "format_restored";
      r.cause = std::string(drivers::to_string(e.cause));
      r.time_ns = e.time_ns;
      r.t_s = 1e-9 * static_cast<double>(e.time_ns - start_ns_);
      r.expected = drivers::format_text(e.expected);
      r.seen = drivers::format_text(e.seen);
      std::fprintf(out_, "%s\n", line(r).c_str());
      std::fflush(out_);
      events_.push_back(std::move(r));
    }
  }
}

std::string CameraEventLog::line(const CameraEventRecord& r) {
  char t[32];
  std::snprintf(t, sizeof t, "%+.3f s", r.t_s);
  std::string s = "  event    " + std::string(t) + " camera " + r.camera + ": ";
  if (r.kind == "format_lost") {
    s += "format lost (" + r.cause + "): delivers " + r.seen + ", not the negotiated " +
         r.expected + "; unusable until it does";
  } else {
    s += "format restored (" + r.cause + "): delivers " + r.expected + " again";
  }
  return s;
}

}  // namespace hd::station
