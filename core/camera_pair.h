#pragma once
// The real/virtual camera pair of a ViewSetup with its frame changes precomputed once per frame,
// and E evaluated from a real-camera-frame point. Shared by E, E_max, coverage and the region.

#include <Eigen/Core>
#include <cmath>
#include <limits>

#include "core/view_setup.h"

namespace hd::core {

class CameraPair {
 public:
  explicit CameraPair(const ViewSetup& s);

  const ViewSetup& setup() const { return s_; }
  /// X_virt = R_vr * X_real + t_vr
  const Eigen::Matrix3d& R_vr() const { return R_vr_; }
  const Eigen::Vector3d& t_vr() const { return t_vr_; }

  Eigen::Vector3d real_from_world(const Eigen::Vector3d& X) const {
    return s_.T_world_real.to_camera(X);
  }
  Eigen::Vector3d virt_from_real(const Eigen::Vector3d& X_r) const { return R_vr_ * X_r + t_vr_; }
  Eigen::Vector3d real_from_virt(const Eigen::Vector3d& X_v) const {
    return R_vr_.transpose() * (X_v - t_vr_);
  }

  /// E at a real-frame point assumed in front of both cameras. Depths are floored at near so a
  /// W vertex that rounding put just outside a near plane still counts as in front (DESIGN 2).
  /// +inf when X'' (the point of z_c = d on the real ray through X) is not in front of the
  /// virtual camera (z <= near), DESIGN 3.
  double error_px(const Eigen::Vector3d& X_r) const {
    const double near = s_.near_m;
    const double z_r = X_r.z() > near ? X_r.z() : near;
    const Eigen::Vector3d X2_r = X_r * (s_.d_m / z_r);
    const Eigen::Vector3d X2_v = virt_from_real(X2_r);
    if (!(X2_v.z() > near)) return std::numeric_limits<double>::infinity();
    Eigen::Vector3d X_v = virt_from_real(X_r);
    if (!(X_v.z() > near)) X_v.z() = near;
    // The principal point cancels in the difference; leaving it out keeps tiny errors exact.
    const double du = s_.virt.fx * (X_v.x() / X_v.z() - X2_v.x() / X2_v.z());
    const double dv = s_.virt.fy * (X_v.y() / X_v.z() - X2_v.y() / X2_v.z());
    return std::hypot(du, dv);
  }

 private:
  const ViewSetup& s_;
  Eigen::Matrix3d R_vr_;
  Eigen::Vector3d t_vr_;
};

inline CameraPair::CameraPair(const ViewSetup& s) : s_(s) {
  const Eigen::Matrix3d Rv_t = s.T_world_virt.R.transpose();
  R_vr_ = Rv_t * s.T_world_real.R;
  t_vr_ = Rv_t * (s.T_world_real.t - s.T_world_virt.t);
}

}  // namespace hd::core
