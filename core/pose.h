#pragma once
// A rigid pose: where a camera (or the head) is in the workspace.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hd::core {

/// Camera-to-world rigid transform T_world_cam (DESIGN.md "Conventions"):
///   X_world = R * X_cam + t,  so t is the camera centre in the world and R's columns are the
/// camera axes (x right, y down, z forward) expressed in the world frame.
/// Compose left to right: T_world_head * T_head_eye = T_world_eye.
struct Pose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  static Pose identity() { return {}; }
  static Pose from(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
    return {q.normalized().toRotationMatrix(), t};
  }

  Eigen::Vector3d to_world(const Eigen::Vector3d& p_cam) const { return R * p_cam + t; }
  Eigen::Vector3d to_camera(const Eigen::Vector3d& p_world) const {
    return R.transpose() * (p_world - t);
  }

  Pose inverse() const { return {R.transpose(), -(R.transpose() * t)}; }
  Pose operator*(const Pose& rhs) const { return {R * rhs.R, R * rhs.t + t}; }

  /// R orthonormal with det +1 (to `tol`) and every entry finite.
  bool valid(double tol = 1e-6) const;
};

}  // namespace hd::core
