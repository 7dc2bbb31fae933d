#include "recon/rectification.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "recon/opencv_camera.h"

namespace hd::recon {

namespace {

// Planar rectification maps the epipole to infinity; with the epipole inside (or just outside)
// an image the warp tears that image apart. The margin, as a share of the image size, keeps the
// strongly converging or forward-moving rigs that OpenCV "rectifies" into a sliver out.
constexpr double kEpipoleMargin = 0.25;

void check_epipole(const core::Pinhole& cam, const core::Pose& T_world_cam,
                   const Eigen::Vector3d& other_centre, const char* name) {
  const Eigen::Vector3d b = T_world_cam.to_camera(other_centre);
  if (std::abs(b.z()) < 1e-12) return;  // epipole at infinity: the ideal case
  const Eigen::Vector2d e = cam.project(b.z() > 0 ? b : Eigen::Vector3d(-b));
  const double mx = kEpipoleMargin * cam.width, my = kEpipoleMargin * cam.height;
  if (e.x() > -mx && e.x() < cam.width + mx && e.y() > -my && e.y() < cam.height + my)
    throw RigError(std::string(name) + " camera: the other camera lies almost along its viewing " +
                   "direction (epipole at pixel (" + std::to_string(e.x()) + ", " +
                   std::to_string(e.y()) + ")): no planar rectification exists for this pair");
}

}  // namespace

Rectification::Rectification(const StereoRig& rig, double alpha) : rig_(rig) {
  rig.check();
  if (rig.left.width != rig.right.width || rig.left.height != rig.right.height)
    throw RigError("left camera is " + std::to_string(rig.left.width) + "x" +
                   std::to_string(rig.left.height) + ", right camera " +
                   std::to_string(rig.right.width) + "x" + std::to_string(rig.right.height) +
                   ": the pair must have one image size");
  check_epipole(rig.left, rig.T_world_left, rig.T_world_right.t, "left");
  check_epipole(rig.right, rig.T_world_right, rig.T_world_left.t, "right");

  size_ = cv::Size(rig.left.width, rig.left.height);
  const cv::Matx33d K1 = opencv_camera_matrix(rig.left), K2 = opencv_camera_matrix(rig.right);
  const cv::Mat D1 = opencv_distortion(rig.left), D2 = opencv_distortion(rig.right);
  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K1, D1, K2, D2, size_, cv::Mat(rig.R_right_left()), cv::Mat(rig.T_right_left()),
                    R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, alpha, size_);
  R1_ = cv::Matx33d(R1);
  R2_ = cv::Matx33d(R2);
  P1_ = cv::Matx34d(P1);
  P2_ = cv::Matx34d(P2);
  Q_ = cv::Matx44d(Q);
  // A horizontal rig has its shift in P2's x (P2(0,3) = -f B for a right camera on the right);
  // OpenCV puts a mostly vertical baseline into P2(1,3) and rows would become columns.
  if (std::abs(P2_(1, 3)) > std::abs(P2_(0, 3)))
    throw RigError(
        "the baseline is mostly vertical in the left camera's view: this matcher "
        "needs a side-by-side pair (rotate both images by 90 degrees first)");
  if (!(P2_(0, 3) < 0.0))
    throw RigError("the right camera is on the left of the left camera: swap left and right");
  focal_px_ = P1_(0, 0);
  baseline_m_ = -P2_(0, 3) / P2_(0, 0);
  if (!(focal_px_ > 0.0) || !std::isfinite(focal_px_) || !(baseline_m_ > 0.0))
    throw RigError("cv::stereoRectify returned a degenerate rectification for this pair");
  cv::initUndistortRectifyMap(K1, D1, R1, P1, size_, CV_32FC1, left_x_, left_y_);
  cv::initUndistortRectifyMap(K2, D2, R2, P2, size_, CV_32FC1, right_x_, right_y_);
}

void Rectification::rectify_left(const cv::Mat& in, cv::Mat& out) const {
  cv::remap(in, out, left_x_, left_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

void Rectification::rectify_right(const cv::Mat& in, cv::Mat& out) const {
  cv::remap(in, out, right_x_, right_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
}

double Rectification::overlap_fraction(double z_near_m, double z_far_m) const {
  constexpr int kCols = 16, kRows = 12, kDepths = 12;
  const core::Pinhole& L = rig_.left;
  const core::Pinhole& R = rig_.right;
  z_near_m = std::max(z_near_m, 1e-3);
  z_far_m = std::max(z_far_m, z_near_m);
  int seen = 0;
  for (int j = 0; j < kRows; ++j) {
    for (int i = 0; i < kCols; ++i) {
      const Eigen::Vector2d uv((i + 0.5) * L.width / kCols, (j + 0.5) * L.height / kRows);
      const Eigen::Vector3d ray = L.ray(uv);
      for (int k = 0; k < kDepths; ++k) {
        const double z =
            z_near_m * std::pow(z_far_m / z_near_m, kDepths == 1 ? 0.0 : double(k) / (kDepths - 1));
        const Eigen::Vector3d X_r =
            rig_.T_world_right.to_camera(rig_.T_world_left.to_world(ray * z));
        if (!(X_r.z() > 1e-6)) continue;
        const Eigen::Vector2d p = R.project(X_r);
        if (p.x() >= 0 && p.x() <= R.width && p.y() >= 0 && p.y() <= R.height) {
          ++seen;
          break;
        }
      }
    }
  }
  return static_cast<double>(seen) / (kCols * kRows);
}

}  // namespace hd::recon
