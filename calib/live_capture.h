#pragma once
// Collects calibration views from running cameras: one camera (views) or two (pairs taken at the
// same instant). A view or pair is kept when the board is found and it differs enough from the
// ones kept, and the collector says when the set is varied enough.

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "calib/corner_detector.h"
#include "calib/coverage.h"
#include "calib/intrinsics_calibration.h"
#include "drivers/camera_source.h"

namespace hd::calib {

struct LiveOptions {
  int target_views = 15;           ///< stop after this many kept views (or pairs) ...
  double min_grid_fraction = 0.6;  ///< ... once they cover this much of the 8x6 grid
  double min_size_ratio = 1.5;  ///< ... and the largest board is this much larger than the smallest
  double min_move_fraction = 0.05;  ///< a new view's corners must move this much of the diagonal
  /// A camera that delivers nothing new for this long is taken as silent, and the run ends.
  std::chrono::milliseconds max_duration{120000};
  /// Pairs: the two frames' exposure times may differ by at most this much; 0 = half the frame
  /// period of the faster camera (its reported rate, else measured from its frames' timestamps).
  int64_t sync_tolerance_ns = 0;
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
/// enough views exist, the camera goes silent (its stream ends, or nothing new for
/// max_duration), or `show` returns false. `source` must be open()ed and start()ed by the caller.
LiveResult collect_live_views(drivers::CameraSource& source, const Board& board,
                              const LiveOptions& opt,
                              const std::function<bool(const LiveStatus&)>& show);

/// What the two-camera loop shows after each examined pair or frame set aside.
struct StereoLiveStatus {
  std::string message;   ///< e.g. "[4/15] pair 37: board found / board found, kept; ..."
  Coverage left, right;  ///< of the kept pairs so far
  bool enough = false;
};

struct StereoLiveResult {
  std::vector<View> left, right;  ///< the kept pairs, same order and names
  cv::Size image_size;
  bool enough = false;
  int frames_left = 0, frames_right = 0;  ///< taken from each camera
  int pairs_examined = 0;                 ///< synchronised pairs the detector ran on
  int unsynchronised = 0;  ///< frames set aside: no frame of the other camera close enough in time
  int board_in_one_only = 0;
  int board_in_neither = 0;
  int too_similar = 0;            ///< board in both, but too close to a kept pair
  int frames_rejected = 0;        ///< malformed frames (wrong size/format), counted and skipped
  int64_t sync_tolerance_ns = 0;  ///< the tolerance used (0: no pair was judged)
  /// Set when the two cameras deliver different sizes ("camera A delivers 640x480 but camera B
  /// delivers 320x240"); the run stops at once.
  std::string size_mismatch;
  std::string stop_reason;  ///< why the loop ended, for the summary line
};

/// Pairs the two cameras' frames by exposure time (Frame::host_timestamp_ns, the one clock): a
/// pair counts when the two frames are within the tolerance and the board is found in both, and
/// is kept when it differs enough from every kept pair in at least one image. Returns when enough
/// varied pairs exist in both images, either camera goes silent, their sizes differ, or `show`
/// returns false. Both sources must be open()ed and start()ed by the caller.
StereoLiveResult collect_live_pairs(drivers::CameraSource& left, drivers::CameraSource& right,
                                    const Board& board, const LiveOptions& opt,
                                    const std::function<bool(const StereoLiveStatus&)>& show);

/// Converts an RGBA8/RGB8/Mono8 frame to gray; empty Mat (and a reason) if malformed.
cv::Mat frame_to_gray(const drivers::Frame& f, std::string* why);

}  // namespace hd::calib
