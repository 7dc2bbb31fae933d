#include "station/video/calibration_difference.h"

#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <vector>

#include "core/opencv_pixels.h"

namespace hd::station {
namespace {

// The raw pixels `uv` (core convention) undistorted with p (core convention out).
std::vector<Eigen::Vector2d> undistorted(const core::Pinhole& p,
                                         const std::vector<Eigen::Vector2d>& uv) {
  const core::OpenCvIntrinsics o = core::to_opencv(p);
  const cv::Matx33d K(o.fx, 0.0, o.cx, 0.0, o.fy, o.cy, 0.0, 0.0, 1.0);
  cv::Mat dist(1, o.distortion_count == 0 ? 4 : o.distortion_count, CV_64F, cv::Scalar(0));
  for (int i = 0; i < o.distortion_count; ++i)
    dist.at<double>(i) = o.distortion[static_cast<std::size_t>(i)];
  std::vector<cv::Point2d> in, out;
  for (const Eigen::Vector2d& q : uv) {
    const Eigen::Vector2d c = core::to_opencv_px(q);
    in.emplace_back(c.x(), c.y());
  }
  cv::undistortPoints(in, out, K, dist, cv::noArray(), K);
  std::vector<Eigen::Vector2d> r;
  for (const cv::Point2d& q : out) r.push_back(core::from_opencv_px({q.x, q.y}));
  return r;
}

}  // namespace

double calibration_difference_px(const core::Pinhole& a, const core::Pose& P_a,
                                 const core::Pinhole& b, const core::Pose& P_b, double depth_m) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!a.valid() || !b.valid() || !P_a.valid() || !P_b.valid() || !(depth_m > 0.0)) return kInf;
  std::vector<Eigen::Vector2d> raw;
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 9; ++i)
      raw.emplace_back(a.width * (0.5 + i) / 9.0, a.height * (0.5 + j) / 7.0);
  const std::vector<Eigen::Vector2d> ua = undistorted(a, raw), ub = undistorted(b, raw);
  double worst = 0.0;
  for (std::size_t k = 0; k < raw.size(); ++k) {
    const Eigen::Vector3d X = P_a.to_world(a.ray(ua[k]) * depth_m);
    const Eigen::Vector3d x_b = P_b.to_camera(X);
    if (!(x_b.z() > 0.0)) return kInf;
    worst = std::max(worst, (b.project(x_b) - ub[k]).norm());
  }
  return worst;
}

}  // namespace hd::station
