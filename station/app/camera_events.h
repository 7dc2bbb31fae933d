#pragma once
// The cameras' format events as the run reports them: taken between frames (never inside the
// tick), printed as a line at the time they are seen, and kept for summary.json.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <span>

#include "station/app/station_camera.h"

namespace hd::station {

/// One FormatEvent of one camera, in the run's words.
struct CameraEventRecord {
  std::string camera;    ///< the camera's name in the station file
  std::string kind;      ///< "format_lost", "format_restored" or "calibration_from_stream"
  std::string cause;     ///< "frame", "source change", "reconnect"
  int64_t time_ns = 0;   ///< CLOCK_MONOTONIC, the driver's time of the event
  double t_s = 0.0;      ///< seconds since the loop started (negative: during start-up)
  std::string expected;  ///< the negotiated format, e.g. "640x480 Mono8 at 30 Hz"
  std::string seen;      ///< what the device delivers now ("size unknown" when it did not say)
};

class CameraEventLog {
 public:
  /// Lines go to `out`; times are reported relative to `start_ns` (CLOCK_MONOTONIC).
  CameraEventLog(std::FILE* out, int64_t start_ns) : out_(out), start_ns_(start_ns) {}

  /// Takes every pending format event of each camera (its device's and its pipeline's) and
  /// prints it.
  void poll(std::span<const StationCamera> cameras);

  /// Takes every calibration the pipelines took from their streams and prints it (the first,
  /// and each with new intrinsics or more than 0.5 px from the camera's calibration file; a
  /// moving camera's new poses are only counted).
  void poll_calibrations(std::span<const StationCamera> cameras);
  /// Stream calibrations taken but not printed (new poses of a moving camera).
  uint64_t pose_revisions() const { return pose_revisions_; }

  const std::vector<CameraEventRecord>& events() const { return events_; }

  /// "event   +6.234 s camera front: format lost (reconnect): delivers 512x512 Mono8, not the
  /// negotiated 320x240 Mono8 at 30 Hz; unusable until it does"
  static std::string line(const CameraEventRecord& r);

 private:
  std::FILE* out_;
  int64_t start_ns_;
  std::vector<CameraEventRecord> events_;
  uint64_t pose_revisions_ = 0;
};

/// A streamed calibration in a line: "640x480, fx 500.00 fy 500.00 cx 319.50 cy 239.50
/// (OpenCV's convention, as in a calibration file), 5 distortion coefficients, centre (x, y, z) m".
std::string calibration_text(const core::Pinhole& p_c, const core::Pose& T_world_cam);

/// A streamed calibration is used instead of the file's; beyond this it is a warning.
inline constexpr double kCalibrationWarnPx = 0.5;

}  // namespace hd::station
