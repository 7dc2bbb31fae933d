#pragma once
// How well the rectification really aligns rows: the vertical offset of image features between
// the rectified left and right images.

#include <opencv2/core.hpp>

namespace hd::recon {

/// Rectified row error: for corners of the rectified left image (Shi-Tomasi) that have a known
/// disparity d, their position in the rectified right image is refined by pyramidal Lucas-Kanade
/// starting at (x - d, y), both horizontally and vertically, and kept only if tracking back lands
/// within 0.5 px of the corner. dy = y_right - y_left in rectified pixels; a perfect calibration
/// gives dy ~ 0 (the matcher itself searches the row only), a vertical calibration error of k px
/// shows up as a median dy near k.
struct RowError {
  int features = 0;            ///< matched corners the figures are over (0: not measured)
  double median_px = 0.0;      ///< median signed dy (a consistent shift: a calibration error)
  double median_abs_px = 0.0;  ///< median |dy|
  double p90_abs_px = 0.0;     ///< 90th percentile of |dy|
  bool measured() const { return features >= kMinFeatures; }
  static constexpr int kMinFeatures = 8;
};

/// `left_grey`, `right_grey`: the rectified pair (CV_8UC1); `disparity`: CV_32F, NaN = unknown.
RowError measure_row_error(const cv::Mat& left_grey, const cv::Mat& right_grey,
                           const cv::Mat& disparity, int max_features = 400);

}  // namespace hd::recon
