#include "station/app/camera_events.h"

#include "core/opencv_pixels.h"

namespace hd::station {

void CameraEventLog::poll(std::span<const StationCamera> cameras) {
  for (const StationCamera& c : cameras) {
    drivers::FormatEvent e;
    while (c.pipeline->pop_format_event(e)) {
      CameraEventRecord r;
      r.camera = c.name;
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

void CameraEventLog::poll_calibrations(std::span<const StationCamera> cameras) {
  for (const StationCamera& c : cameras) {
    CalibrationEvent e;
    while (c.pipeline->pop_calibration_event(e)) {
      const bool warn = e.differs_from_file_px > kCalibrationWarnPx;
      if (!e.first && !e.intrinsics_changed && !warn) {
        ++pose_revisions_;
        continue;
      }
      CameraEventRecord r;
      r.camera = c.name;
      r.kind = "calibration_from_stream";
      r.cause = "revision " + std::to_string(e.revision);
      r.time_ns = e.time_ns;
      r.t_s = 1e-9 * static_cast<double>(e.time_ns - start_ns_);
      r.seen = calibration_text(e.p_c, e.T_world_cam);
      const std::string& file = c.description.calibration_file;
      if (!file.empty()) {
        char d[160];
        std::snprintf(
            d, sizeof d, "%s by %.3f px (at the plane distance d)",
            warn ? "WARNING: differs from the file by more than 0.5 px:" : "differs from the file",
            e.differs_from_file_px);
        r.expected = std::string(d) + "; the stream's replaces " + file;
      }
      std::fprintf(out_, "%s\n", line(r).c_str());
      std::fflush(out_);
      events_.push_back(std::move(r));
    }
  }
}

std::string calibration_text(const core::Pinhole& p_c, const core::Pose& T) {
  const core::OpenCvIntrinsics k = core::to_opencv(p_c);
  char b[320];
  std::snprintf(b, sizeof b,
                "%dx%d, fx %.2f fy %.2f cx %.2f cy %.2f (OpenCV's convention, as in a calibration "
                "file), %d distortion coefficients, centre (%.3f, %.3f, %.3f) m",
                k.width, k.height, k.fx, k.fy, k.cx, k.cy, k.distortion_count, T.t.x(), T.t.y(),
                T.t.z());
  return b;
}

std::string CameraEventLog::line(const CameraEventRecord& r) {
  char t[32];
  std::snprintf(t, sizeof t, "%+.3f s", r.t_s);
  std::string s = "  event    " + std::string(t) + " camera " + r.camera + ": ";
  if (r.kind == "calibration_from_stream") {
    s += "calibration: from the stream (" + r.cause + "): " + r.seen +
         (r.expected.empty() ? "" : "; " + r.expected);
  } else if (r.kind == "format_lost") {
    s += "format lost (" + r.cause + "): delivers " + r.seen + ", not the negotiated " +
         r.expected + "; unusable until it does";
  } else {
    s += "format restored (" + r.cause + "): delivers " + r.expected + " again";
  }
  return s;
}

}  // namespace hd::station
