#pragma once
// Calibrates on disjoint halves of the views and compares the two models over the image: a low
// RMS with a large disagreement means the views do not pin the model down.

#include "calib/intrinsics_calibration.h"

namespace hd::calib {

struct CrossValidation {
  bool computed = false;  ///< false when there are too few views (< 6) to split
  double max_px = 0.0;    ///< over the whole image (extrapolation included)
  double rms_px = 0.0;
  double covered_max_px = 0.0;  ///< over grid points inside the hull of all detected corners
  double covered_rms_px = 0.0;
  int views_a = 0, views_b = 0;
};

/// Disagreement in pixels between two calibrations of one camera, over a grid_cols x grid_rows
/// grid of pixels: each pixel is unprojected through model A, turned by the rotation that best
/// aligns A's rays with B's over the covered points, and reprojected through model B.
/// The covered_* figures use the grid points inside `covered_hull` (all of them if it is empty).
CrossValidation compare_models(const cv::Matx33d& K_a, const cv::Mat& D_a, const cv::Matx33d& K_b,
                               const cv::Mat& D_b, cv::Size image_size,
                               const std::vector<cv::Point2f>& covered_hull = {},
                               int grid_cols = 32, int grid_rows = 24);

/// Even-indexed views vs odd-indexed views (interleaved so both halves span the session).
/// `start`, if given (the calibration on all views), seeds both halves' optimisation: each half
/// still converges to its own minimum, in a few iterations instead of from scratch.
CrossValidation cross_validate(const std::vector<View>& views, const Board& board,
                               cv::Size image_size, const DistortionModel& model,
                               const IntrinsicsResult* start = nullptr);

}  // namespace hd::calib
