#pragma once
// Collects calibration views from a running camera: keeps a frame when the board is found and
// the view differs enough from the ones kept, and says when the set is varied enough.

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include "calib/corner_detector.h"
#include "calib/coverage.h"
#include "calib/intrinsics_calibration.h"
#include "drivers/camera_source.h"

namespace hd::calib {

struct LiveOptions {
  int target_views = 15;           ///< stop after this many kept views ...
  double min_grid_fraction = 0.6;  ///< ... once they cover this much of the 8x6 grid
  double min_size_ratio = 1.5;  ///< ... and the largest board is this much larger than the smallest
  double min_move_fraction = 0.05;  ///< a new view's corners must move this much of the diagonal
  std::chrono::milliseconds max_duration{120000};
  DetectorOptions detector;
};

/// What the live loop shows after each examined frame.
struct LiveStatus {
  std::string message;  ///< progress line, e.g. "[4/15] frame 37: board found, kept"
  const cv::Mat* gray = nullptr;
  const std::vector<cv::Point2f>* corners = nullptr;  ///< empty when not found
  Coverage coverage;                                  ///< of the kept views so far
  bool enough = false;
};

struct LiveResult {
  std::vector<View> views;
  cv::Size image_size;
  bool enough = false;
  int frames_examined = 0;
  int frames_rejected = 0;  ///< malformed frames (wrong size/format), counted and skipped
};

/// Keeps views in memory; calls `show` after each frame (window or terminal). Returns when
/// enough views exist, the camera stops delivering for max_duration, or `show` returns false.
/// `source` must be open()ed and start()ed by the caller.
LiveResult collect_live_views(drivers::CameraSource& source, const Board& board,
                              const LiveOptions& opt,
                              const std::function<bool(const LiveStatus&)>& show);

/// Converts an RGBA8/RGB8/Mono8 frame to gray; empty Mat (and a reason) if malformed.
cv::Mat frame_to_gray(const drivers::Frame& f, std::string* why);

}  // namespace hd::calib
