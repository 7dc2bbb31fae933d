#pragma once
// A pinhole camera's intrinsics (p_c for a real camera, p_o for the operator's virtual camera).

#include <Eigen/Core>
#include <array>
#include <optional>

namespace hd::core {

/// Pinhole intrinsics with OpenCV axes: x right, y down, z forward (DESIGN.md "Conventions").
///
/// A camera-frame point (x, y, z) with z > 0 projects to
///   u = fx * x / z + cx,   v = fy * y / z + cy
/// and the image spans the continuous rectangle [0, width] x [0, height] (pixel centres at +0.5).
/// `distortion` holds OpenCV's coefficients (k1, k2, p1, p2, k3, ...) as calibrated; the geometry
/// in core works on the undistorted pinhole, the compositor undistorts frames before use.
struct Pinhole {
  double fx = 1.0;
  double fy = 1.0;
  double cx = 0.0;
  double cy = 0.0;
  int width = 0;
  int height = 0;
  std::array<double, 8> distortion{};  ///< OpenCV order; unused entries are zero.
  int distortion_count = 0;            ///< How many of `distortion` were calibrated (0, 4, 5, 8).

  /// Projects a camera-frame point; the caller guarantees z > 0.
  Eigen::Vector2d project(const Eigen::Vector3d& p_cam) const {
    return {fx * p_cam.x() / p_cam.z() + cx, fy * p_cam.y() / p_cam.z() + cy};
  }

  /// The camera-frame ray through pixel (u, v), scaled to z = 1.
  Eigen::Vector3d ray(const Eigen::Vector2d& uv) const {
    return {(uv.x() - cx) / fx, (uv.y() - cy) / fy, 1.0};
  }

  /// Square pixels (fx = fy = f) with the principal point at the image centre.
  static Pinhole centred(double f, int width_px, int height_px) {
    Pinhole k;
    k.fx = k.fy = f;
    k.cx = width_px / 2.0;
    k.cy = height_px / 2.0;
    k.width = width_px;
    k.height = height_px;
    return k;
  }

  /// Finite, positive focal lengths and a non-empty image.
  bool valid() const;

  double area_px() const { return static_cast<double>(width) * static_cast<double>(height); }
};

}  // namespace hd::core
