#include "core/plane_homography.h"

namespace hd::core {

Eigen::Matrix3d virtual_to_real_homography(const ViewSetup& s) {
  if (!s.valid()) return Eigen::Matrix3d::Zero();
  const Pose T_real_virt = s.T_world_real.inverse() * s.T_world_virt;
  const Eigen::Vector3d& t = T_real_virt.t;
  Eigen::Matrix3d K_c;
  K_c << s.real.fx, 0.0, s.real.cx, 0.0, s.real.fy, s.real.cy, 0.0, 0.0, 1.0;
  Eigen::Matrix3d K_o_inv;
  K_o_inv << 1.0 / s.virt.fx, 0.0, -s.virt.cx / s.virt.fx, 0.0, 1.0 / s.virt.fy,
      -s.virt.cy / s.virt.fy, 0.0, 0.0, 1.0;
  // A virtual ray r (real frame: R r) meets n.X = d at X = t + s R r with s = (d - t_z)/(e_z.R r);
  // scaling by (e_z.R r) gives (d - t_z) R r + t (e_z^T R r).
  Eigen::Matrix3d M = (s.d_m - t.z()) * Eigen::Matrix3d::Identity();
  M.col(2) += t;
  // The third coordinate is then d (R r)_z; flipping the sign when the virtual camera is beyond
  // the plane makes it positive exactly when the ray meets the plane in front of that camera.
  const double sign = s.d_m - t.z() < 0.0 ? -1.0 : 1.0;
  return sign * (K_c * M * T_real_virt.R * K_o_inv);
}

}  // namespace hd::core
