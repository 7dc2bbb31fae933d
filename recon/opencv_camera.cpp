#include "recon/opencv_camera.h"

#include <stdexcept>
#include <string>

namespace hd::recon {

namespace {
// core's continuous coordinate of OpenCV's pixel 0 centre.
constexpr double kCentreOffsetPx = 0.5;
}  // namespace

cv::Matx33d opencv_camera_matrix(const core::Pinhole& p) {
  return {p.fx, 0.0, p.cx - kCentreOffsetPx, 0.0, p.fy, p.cy - kCentreOffsetPx, 0.0, 0.0, 1.0};
}

cv::Mat opencv_distortion(const core::Pinhole& p) {
  if (p.distortion_count <= 0) return {};
  cv::Mat d(1, p.distortion_count, CV_64F);
  for (int i = 0; i < p.distortion_count; ++i)
    d.at<double>(i) = p.distortion[static_cast<std::size_t>(i)];
  return d;
}

core::Pinhole pinhole_from_opencv(const cv::Matx33d& K, const cv::Mat& distortion, int width,
                                  int height) {
  core::Pinhole p;
  p.fx = K(0, 0);
  p.fy = K(1, 1);
  p.cx = K(0, 2) + kCentreOffsetPx;
  p.cy = K(1, 2) + kCentreOffsetPx;
  p.width = width;
  p.height = height;
  const int n = static_cast<int>(distortion.total());
  if (n != 0 && n != 4 && n != 5 && n != 8)
    throw std::invalid_argument("expected 0, 4, 5 or 8 distortion coefficients, got " +
                                std::to_string(n));
  cv::Mat d;
  if (n > 0) distortion.reshape(1, 1).convertTo(d, CV_64F);
  p.distortion_count = n;
  for (int i = 0; i < n; ++i) p.distortion[static_cast<std::size_t>(i)] = d.at<double>(i);
  return p;
}

}  // namespace hd::recon
