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
  bool check_larger = true;     ///< reject a pattern that is part of a larger board
  std::chrono::milliseconds timeout{5000};
};

/// kLargerBoard: the detectors found the pattern, but it is part of a larger chessboard (the
/// classic detector happily returns an 8x6 patch of a 9x6 board): a wrong --board.
enum class DetectionStatus { kFound, kNotFound, kTimedOut, kLargerBoard };

struct Detection {
  DetectionStatus status = DetectionStatus::kNotFound;
  bool by_sb = false;  ///< found by the SB detector (fallback)
  std::vector<cv::Point2f> corners;
  int larger_corner_count = 0;  ///< kLargerBoard: corners of the larger board SB saw
  double seconds = 0.0;

  bool found() const { return status == DetectionStatus::kFound; }
  /// "board found", "board found (SB fallback)", "no board", "timed out after 5 s"
  std::string describe() const;
};

/// Runs detection in a worker thread; if the deadline passes, the worker is abandoned (it owns a
/// copy of the image and finishes on its own) and kTimedOut is returned, so a pathological frame
/// cannot hang the tool. `gray` must be 8-bit single channel.
Detection detect_corners(const cv::Mat& gray, const Board& board, const DetectorOptions& opt);

}  // namespace hd::calib
