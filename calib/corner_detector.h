#pragma once
// Finds a chessboard's inner corners in one image, with a deadline.

#include <chrono>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calib/board.h"

namespace hd::calib {

/// How corners are refined after detection (a benchmarked knob: accuracy vs time).
/// kSubPix11 / kSubPix5: cornerSubPix winSize 11 / 5 (half sizes: 23x23 / 11x11 windows).
enum class Refinement { kNone, kSubPix5, kSubPix11 };

struct DetectorOptions {
  Refinement refinement = Refinement::kSubPix11;
  bool use_classic = true;      ///< findChessboardCorners first
  bool use_sb_fallback = true;  ///< findChessboardCornersSB when the classic one fails
  bool check_larger = true;  ///< reject a pattern that is part of a larger board (probe, then SB)
  std::chrono::milliseconds timeout{5000};
};

/// kLargerBoard: the detectors found the pattern, but it is part of a larger chessboard (the
/// classic detector happily returns an 8x6 patch of a 9x6 board): a wrong --board.
enum class DetectionStatus { kFound, kNotFound, kTimedOut, kLargerBoard };

struct Detection {
  DetectionStatus status = DetectionStatus::kNotFound;
  bool by_sb = false;  ///< found by the SB detector (fallback)
  std::vector<cv::Point2f> corners;
  int larger_corner_count = 0;      ///< kLargerBoard: corners of the larger board SB saw
  double seconds = 0.0;             ///< wall time
  double cpu_s = 0.0;               ///< CPU time of the detection thread, all of it
  double larger_check_cpu_s = 0.0;  ///< the part spent on the larger-board check

  bool found() const { return status == DetectionStatus::kFound; }
  /// "board found", "board found (SB fallback)", "no board", "timed out after 5 s"
  std::string describe() const;
};

/// The inner corners of the larger chessboard the COLSxROWS pattern is part of
/// (findChessboardCornersSB with CALIB_CB_LARGER), 0 if it is not part of one. As costly as a
/// detection, and fooled by steep views of a board with a white margin: run only where
/// probe_beyond_edges (calib/larger_board_probe.h) sees the checker go on past an edge.
int larger_board_corners(const cv::Mat& gray, const Board& board);

/// Runs detection in a worker thread; if the deadline passes, the worker is abandoned (it owns a
/// copy of the image and finishes on its own) and kTimedOut is returned, so a pathological frame
/// cannot hang the tool while it runs; at exit the process waits for abandoned workers, which
/// must not be inside OpenCV when its statics go. `gray` must be 8-bit single channel.
Detection detect_corners(const cv::Mat& gray, const Board& board, const DetectorOptions& opt);

}  // namespace hd::calib
