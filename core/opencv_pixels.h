#pragma once
// The one place that converts between core's pixel convention and OpenCV's (DESIGN.md
// "Conventions"): every calibration file, camera matrix handed to OpenCV and OpenCV result read
// back goes through these functions, so no other file adds or subtracts the half pixel.

#include <Eigen/Core>
#include <array>
#include <stdexcept>
#include <string>

#include "core/pinhole.h"

namespace hd::core {

/// core::Pinhole spans [0, width] x [0, height] with pixel (i, j)'s centre at (i + 0.5, j + 0.5);
/// OpenCV (and ROS, and the calibration files) put that centre at (i, j). The same lens therefore
/// has its principal point kOpenCvOffsetPx smaller in OpenCV's numbers; focal lengths, distortion
/// coefficients and image size are the same in both.
inline constexpr double kOpenCvOffsetPx = 0.5;

/// An image point in core's continuous coordinates as OpenCV numbers it, and back.
inline Eigen::Vector2d to_opencv_px(const Eigen::Vector2d& core_px) {
  return core_px.array() - kOpenCvOffsetPx;
}
inline Eigen::Vector2d from_opencv_px(const Eigen::Vector2d& opencv_px) {
  return opencv_px.array() + kOpenCvOffsetPx;
}

/// The entries of OpenCV's camera matrix K = [fx 0 cx; 0 fy cy; 0 0 1] (no skew), in OpenCV's
/// convention, with the distortion coefficients in OpenCV's order (0, 4, 5 or 8 of them).
struct OpenCvIntrinsics {
  double fx = 1.0, fy = 1.0, cx = 0.0, cy = 0.0;
  int width = 0, height = 0;
  std::array<double, 8> distortion{};
  int distortion_count = 0;
};

/// core -> OpenCV: the principal point moves by -kOpenCvOffsetPx, nothing else changes.
inline OpenCvIntrinsics to_opencv(const Pinhole& p) {
  OpenCvIntrinsics o;
  o.fx = p.fx;
  o.fy = p.fy;
  const Eigen::Vector2d c = to_opencv_px({p.cx, p.cy});
  o.cx = c.x();
  o.cy = c.y();
  o.width = p.width;
  o.height = p.height;
  o.distortion = p.distortion;
  o.distortion_count = p.distortion_count;
  return o;
}

/// OpenCV -> core, the inverse of to_opencv. Throws std::invalid_argument for a distortion count
/// other than 0, 4, 5 or 8.
inline Pinhole from_opencv(const OpenCvIntrinsics& o) {
  const int n = o.distortion_count;
  if (n != 0 && n != 4 && n != 5 && n != 8)
    throw std::invalid_argument("expected 0, 4, 5 or 8 distortion coefficients, got " +
                                std::to_string(n));
  Pinhole p;
  p.fx = o.fx;
  p.fy = o.fy;
  const Eigen::Vector2d c = from_opencv_px({o.cx, o.cy});
  p.cx = c.x();
  p.cy = c.y();
  p.width = o.width;
  p.height = o.height;
  p.distortion = o.distortion;
  p.distortion_count = n;
  return p;
}

}  // namespace hd::core
