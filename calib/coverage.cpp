#include "calib/coverage.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace hd::calib {

Coverage image_coverage(const std::vector<std::vector<cv::Point2f>>& corners, cv::Size image_size) {
  Coverage c;
  c.occupancy = cv::Mat::zeros(Coverage::kGridRows, Coverage::kGridCols, CV_32S);
  const double area = static_cast<double>(image_size.area());
  std::vector<cv::Point2f> all;
  bool first = true;
  for (const auto& view : corners) {
    if (view.size() < 3) continue;
    all.insert(all.end(), view.begin(), view.end());
    std::vector<cv::Point2f> hull;
    cv::convexHull(view, hull);
    const double f = cv::contourArea(hull) / area;
    c.board_size_min = first ? f : std::min(c.board_size_min, f);
    c.board_size_max = first ? f : std::max(c.board_size_max, f);
    first = false;
    for (const auto& p : view) {
      const int gx = std::clamp(static_cast<int>(p.x / image_size.width * Coverage::kGridCols), 0,
                                Coverage::kGridCols - 1);
      const int gy = std::clamp(static_cast<int>(p.y / image_size.height * Coverage::kGridRows), 0,
                                Coverage::kGridRows - 1);
      ++c.occupancy.at<int>(gy, gx);
    }
  }
  if (all.size() >= 3) {
    std::vector<cv::Point2f> hull;
    cv::convexHull(all, hull);
    c.hull_fraction = cv::contourArea(hull) / area;
  }
  c.grid_fraction = static_cast<double>(cv::countNonZero(c.occupancy)) /
                    (Coverage::kGridCols * Coverage::kGridRows);
  return c;
}

Coverage coverage(const std::vector<View>& views, const IntrinsicsResult& result) {
  std::vector<std::vector<cv::Point2f>> corners;
  for (const auto& v : views) corners.push_back(v.corners);
  Coverage c = image_coverage(corners, result.image_size);
  bool first = true;
  for (const auto& v : result.views) {
    cv::Matx33d R;
    cv::Rodrigues(v.rvec, R);
    // The board normal in the camera frame is R's third column; 0 deg = board facing the camera.
    const double tilt = std::acos(std::min(1.0, std::abs(R(2, 2)))) * 180.0 / CV_PI;
    c.tilt_min_deg = first ? tilt : std::min(c.tilt_min_deg, tilt);
    c.tilt_max_deg = first ? tilt : std::max(c.tilt_max_deg, tilt);
    first = false;
  }
  return c;
}

}  // namespace hd::calib
