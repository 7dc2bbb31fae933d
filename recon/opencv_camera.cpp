#include "recon/opencv_camera.h"

#include "core/opencv_pixels.h"

namespace hd::recon {

cv::Matx33d opencv_camera_matrix(const core::Pinhole& pinhole) {
  const core::OpenCvIntrinsics p = core::to_opencv(pinhole);
  return {p.fx, 0.0, p.cx, 0.0, p.fy, p.cy, 0.0, 0.0, 1.0};
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
  core::OpenCvIntrinsics o;
  o.fx = K(0, 0);
  o.fy = K(1, 1);
  o.cx = K(0, 2);
  o.cy = K(1, 2);
  o.width = width;
  o.height = height;
  const int n = static_cast<int>(distortion.total());
  o.distortion_count = n;
  if (n > 0 && n <= static_cast<int>(o.distortion.size())) {
    cv::Mat d;
    distortion.reshape(1, 1).convertTo(d, CV_64F);
    for (int i = 0; i < n; ++i) o.distortion[static_cast<std::size_t>(i)] = d.at<double>(i);
  }
  return core::from_opencv(o);  // throws std::invalid_argument for a count other than 0/4/5/8
}

}  // namespace hd::recon
