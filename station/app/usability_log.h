#pragma once
// When each camera was usable (streaming, video younger than its bound) and when not, as the run
// reports it: taken from the station frame between frames, printed as an event line when seen,
// and kept as per-camera unusable intervals for summary.json.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "station/frame/station_frame.h"

namespace hd::station {

/// One stretch of frames in which a camera that had delivered video was not usable.
struct UnusableInterval {
  double from_s = 0.0;  ///< display time of its first frame, seconds since the loop started
  double to_s = -1.0;   ///< display time of the first frame it was usable again (-1: never)
  uint64_t from_frame = 0, to_frame = 0;
  double age_at_start_ms = 0.0;  ///< the newest frame's age when it became unusable
  /// The first frame the camera delivered after it became unusable (CLOCK_MONOTONIC, 0: none).
  int64_t first_new_frame_ns = 0;
  int64_t to_display_ns = 0;  ///< display time of the first frame it was usable again
  std::string state;          ///< the source's state then ("streaming": too old)
};

class UsabilityLog {
 public:
  UsabilityLog(std::FILE* out, int64_t start_ns, std::size_t cameras)
      : out_(out), start_ns_(start_ns), intervals_(cameras) {}

  /// Takes every pending usability change of `frame` and prints it (`names[i]` names camera i).
  void poll(StationFrame& frame, const std::vector<std::string>& names);

  /// intervals()[camera]: in the order they happened.
  const std::vector<std::vector<UnusableInterval>>& intervals() const { return intervals_; }

  /// "  event    +6.234 s camera front: unusable from frame 540 (video 121 ms old, stalled):
  /// not shown as live video" / "... usable from frame 990 (video 25 ms old)".
  static std::string line(const std::string& camera, const CameraUsabilityEvent& e, double t_s);

 private:
  std::FILE* out_;
  int64_t start_ns_;
  std::vector<std::vector<UnusableInterval>> intervals_;
};

}  // namespace hd::station
