#pragma once
// calibrateCamera over the views where a board was found, with the figures that say how
// far to trust the result.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/distortion_model.h"

namespace hd::calib {

/// One image where the board was found.
struct View {
  std::string name;
  std::vector<cv::Point2f> corners;
};

struct ViewResult {
  std::string name;
  double rms_px = 0.0;
  bool outlier = false;
  cv::Vec3d rvec, tvec;                   ///< board-to-camera (OpenCV's extrinsics)
  std::vector<cv::Point2f> residuals_px;  ///< detected minus reprojected, per corner
};

struct IntrinsicsResult {
  cv::Size image_size;
  cv::Matx33d camera_matrix;
  cv::Mat distortion;   ///< 1xN double (N = 5 or 8)
  double rms_px = 0.0;  ///< overall RMS over all corners
  std::vector<ViewResult> views;
  int worst_view = -1;
  cv::Mat std_dev_intrinsics;  ///< 1x(4+N): fx fy cx cy then distortion terms
  int flags = 0;

  double fx() const { return camera_matrix(0, 0); }
  double fy() const { return camera_matrix(1, 1); }
  double cx() const { return camera_matrix(0, 2); }
  double cy() const { return camera_matrix(1, 2); }
  double sigma(int i) const { return std_dev_intrinsics.at<double>(0, i); }
};

/// A view is an outlier only if it is also this much worse than the median view: among views
/// near 0.05 px, one at 0.062 px is not worth a warning however the others scatter.
inline constexpr double kOutlierFloorPx = 0.1;

/// Which views are outliers, from the per-view RMS (px): relative (above 2x the median or above
/// mean + 3 sigma) and absolute (more than kOutlierFloorPx above the median) at once.
std::vector<bool> outlier_views(const std::vector<double>& rms_px);

/// Calibrates; needs >= 3 views (throws std::runtime_error otherwise). Outlier views: per-view RMS
/// above 2x the median or above mean + 3 sigma of the per-view RMS (relative), and more than
/// kOutlierFloorPx above the median (absolute). `start`, if given, is the initial guess
/// (CALIB_USE_INTRINSIC_GUESS) instead of OpenCV's own initialisation. `with_sigma` false leaves
/// std_dev_intrinsics empty (intrinsics_std_dev computes it, for timing it on its own).
IntrinsicsResult calibrate_intrinsics(const std::vector<View>& views, const Board& board,
                                      cv::Size image_size, const DistortionModel& model,
                                      const IntrinsicsResult* start = nullptr,
                                      bool with_sigma = true);

}  // namespace hd::calib
