#pragma once
// Chessboard views of a known camera, for benchmarks and statistical tests: the truth is known
// exactly, so recovered intrinsics and poses can be scored.

#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "calib/board.h"

namespace hd::calib {

struct SyntheticCamera {
  cv::Matx33d K;
  cv::Mat D;  ///< 1x5 (k1 k2 p1 p2 k3)
  cv::Size size;
};

struct BoardPose {
  cv::Vec3d rvec, tvec;  ///< board-to-camera
};

/// A random pose that keeps the whole board (with its one-square margin) in the image:
/// board width 30-70% of the image, tilt up to `max_tilt_deg` about two axes, in-plane turn
/// within +-30 deg (so the detector's numbering never flips).
BoardPose random_board_pose(const SyntheticCamera& cam, const Board& board, std::mt19937& rng,
                            double max_tilt_deg = 35.0);

/// True corner projections (with distortion).
std::vector<cv::Point2f> project_corners(const SyntheticCamera& cam, const Board& board,
                                         const BoardPose& pose);

/// Precomputed undistorted rays of every sub-pixel sample; reuse across views of one camera.
class SyntheticRenderer {
 public:
  SyntheticRenderer(const SyntheticCamera& cam, int supersample = 3);
  /// Renders the board (black origin square, white margin, grey surround) anti-aliased by
  /// supersampling, then Gaussian blur `blur_sigma_px` (0 = none) and noise `noise_sigma` grey
  /// levels. 8-bit gray.
  cv::Mat render(const Board& board, const BoardPose& pose, double blur_sigma_px,
                 double noise_sigma, std::mt19937& rng) const;

 private:
  SyntheticCamera cam_;
  int ss_;
  cv::Mat rays_;  ///< (H*ss) x (W*ss) CV_32FC2: normalised undistorted coordinates
};

}  // namespace hd::calib
