#pragma once
// Rotation-vector <-> unit quaternion maps, the tangent space the predictors work in.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace hd::station {

/// exp: rotation vector (axis * angle, rad) to unit quaternion. Exact for every angle; the small
/// angle branch keeps the result finite and accurate near zero.
inline Eigen::Quaterniond so3_exp(const Eigen::Vector3d& v_rad) {
  const double angle = v_rad.norm();
  if (angle < 1e-9) {
    // Second-order series: cos(a/2) ~ 1 - a^2/8, sin(a/2)/a ~ 1/2.
    return Eigen::Quaterniond(1.0 - angle * angle / 8.0, 0.5 * v_rad.x(), 0.5 * v_rad.y(),
                              0.5 * v_rad.z())
        .normalized();
  }
  const double s = std::sin(0.5 * angle) / angle;
  return Eigen::Quaterniond(std::cos(0.5 * angle), s * v_rad.x(), s * v_rad.y(), s * v_rad.z());
}

/// log: unit quaternion to the rotation vector of the shortest rotation it represents (|v| <= pi).
inline Eigen::Vector3d so3_log(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // q and -q are the same rotation; take the short way
  const Eigen::Vector3d vec = q.vec();
  const double s = vec.norm();
  if (s < 1e-12) return 2.0 * vec;  // angle ~ 2 s
  return (2.0 * std::atan2(s, q.w()) / s) * vec;
}

/// Angle (rad) between two orientations.
inline double angle_between_rad(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return so3_log(a.conjugate() * b).norm();
}

/// Skew-symmetric matrix: skew(a) * b = a x b.
inline Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

}  // namespace hd::station
