#include "render/compositor/video_warp.h"

#include <cmath>

namespace hd::render {

VideoWarp VideoWarp::make(const core::Pinhole& eye, const core::Pose& T_world_eye,
                          const core::Pinhole& real, const core::Pose& T_world_real, double d_m) {
  VideoWarp w;
  if (!(d_m > 0.0) || !std::isfinite(d_m) || !eye.valid() || !real.valid()) return w;
  // X_real = R X_eye + t. The plane n^T X_real = d (n = z axis) in the eye frame is
  // n_o^T X_eye = d_o with n_o = R^T n, d_o = d - t_z (signed distance of the eye from it).
  const core::Pose T_real_eye = T_world_real.inverse() * T_world_eye;
  const Eigen::Matrix3d& R = T_real_eye.R;
  const Eigen::Vector3d& t = T_real_eye.t;
  const Eigen::Vector3d n_o = R.transpose().col(2);
  const double d_o = d_m - t.z();
  if (!(std::abs(d_o) > 1e-12) || !R.allFinite() || !t.allFinite()) return w;
  Eigen::Matrix3d K_o_inv;
  K_o_inv << 1.0 / eye.fx, 0, -eye.cx / eye.fx, 0, 1.0 / eye.fy, -eye.cy / eye.fy, 0, 0, 1;
  Eigen::Matrix3d K_c;
  K_c << real.fx, 0, real.cx, 0, real.fy, real.cy, 0, 0, 1;
  // On the plane X_real = (R + t n_o^T / d_o) X_eye; with X_eye = z_eye K_o^-1 p this gives
  // H p = K_c X_real / z_eye, whose third entry is d / z_eye.
  w.H = K_c * (R + t * n_o.transpose() / d_o) * K_o_inv;
  w.inv_depth = K_o_inv.transpose() * n_o / d_o;
  w.usable = w.H.allFinite() && w.inv_depth.allFinite();
  return w;
}

}  // namespace hd::render
