#pragma once
// The standard deviations of calibrated intrinsics, from the Jacobian at the solution.

#include <opencv2/core.hpp>
#include <vector>

#include "calib/board.h"
#include "calib/intrinsics_calibration.h"

namespace hd::calib {

/// 1x(4+N) standard deviations of fx fy cx cy and the N distortion terms of `r` (its camera
/// matrix, distortion, per-view poses and OpenCV flags), as calibrateCameraExtended reports them
/// (OpenCV 4.6, Debian 12's: sqrt(diag((J^T J)^-1) * |e|^2 / (corners - free parameters)), at
/// the solution), but with the intrinsic block of (J^T J)^-1 taken through the Schur complement of
/// the per-view 6x6 pose blocks instead of inverting the whole (4 + N + 6 * views)-square matrix
/// by SVD: ~0.5 ms instead of ~5 ms for the 13 shared views. Fixed terms get 0; with a fixed
/// aspect ratio fx shares fy's sigma (OpenCV reports 0 for it).
cv::Mat intrinsics_std_dev(const std::vector<View>& views, const Board& board,
                           const IntrinsicsResult& r);

}  // namespace hd::calib
