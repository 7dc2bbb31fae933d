#pragma once
// Which part of the image, which board sizes and which tilts the views covered (the ROS
// calibrator's idea): what a technician should add next.

#include <opencv2/core.hpp>
#include <vector>

#include "calib/intrinsics_calibration.h"

namespace hd::calib {

struct Coverage {
  static constexpr int kGridCols = 8;
  static constexpr int kGridRows = 6;
  double hull_fraction = 0.0;  ///< area of the convex hull of all corners / image area
  cv::Mat occupancy;           ///< kGridRows x kGridCols CV_32S: corners per cell
  double grid_fraction = 0.0;  ///< fraction of cells holding at least one corner
  double board_size_min = 0.0, board_size_max = 0.0;  ///< per-view hull area / image area
  double tilt_min_deg = 0.0, tilt_max_deg = 0.0;      ///< angle of board normal to the optical axis
};

/// From the detected corners alone (works live, before any calibration).
Coverage image_coverage(const std::vector<std::vector<cv::Point2f>>& corners, cv::Size image_size);

/// Adds the tilt range from the calibrated extrinsics.
Coverage coverage(const std::vector<View>& views, const IntrinsicsResult& result);

}  // namespace hd::calib
