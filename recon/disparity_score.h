#pragma once
// Scores a disparity map against ground truth the way Middlebury and KITTI do (bad-tau, holes
// counted as bad or filled first, non-occluded pixels), for the tests and benchmarks.

#include <opencv2/core.hpp>

namespace hd::recon {

/// Ground-truth disparity (CV_32F, 0 or NaN = unknown) -> CV_8U mask of the non-occluded known
/// pixels: the match x - d lies inside the image and no nearer surface (a larger disparity more
/// than `occlusion_tolerance_px` above) lands on the same right pixel (forward warp).
cv::Mat non_occluded_mask(const cv::Mat& truth, float occlusion_tolerance_px = 1.0f);

/// Fills unknown pixels (NaN) row by row with the smaller (farther) of the nearest known
/// disparities to the left and right: the usual background fill before "filled" scores.
cv::Mat fill_holes(const cv::Mat& disparity);

struct DisparityScore {
  int pixels = 0;              ///< scored pixels (the mask)
  double density = 0.0;        ///< share of them with an estimate
  double bad_holes = 0.0;      ///< share with |d - truth| > tau or no estimate
  double bad_filled = 0.0;     ///< the same after fill_holes
  double bad_known = 0.0;      ///< among pixels with an estimate only
  double median_abs_px = 0.0;  ///< median |d - truth| over pixels with an estimate
};

/// `disparity` CV_32F, NaN = unknown; `truth` CV_32F; `mask` CV_8U (non-zero = scored).
DisparityScore score_disparity(const cv::Mat& disparity, const cv::Mat& truth, const cv::Mat& mask,
                               double tau_px);

}  // namespace hd::recon
