#pragma once
// The report picture: where the corners were, how they miss the model, what is not covered.

#include <opencv2/core.hpp>

#include "calib/coverage.h"
#include "calib/intrinsics_calibration.h"

namespace hd::calib {

/// Residual vectors are drawn this many times longer than they are.
constexpr double kResidualMagnification = 50.0;

/// Left panel: `background` (gray, dimmed) with every corner and its residual vector x50 (outlier
/// views in red); right panel: the 8x6 coverage heat map; a legend below. BGR 8-bit.
cv::Mat render_report(const cv::Mat& background, const std::vector<View>& views,
                      const IntrinsicsResult& r, const Coverage& c);

}  // namespace hd::calib
