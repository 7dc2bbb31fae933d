#pragma once
// The GL passes' camera: a pinhole at a workspace pose as one world-to-clip matrix.

#include <Eigen/Core>

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::render::gl {

/// Camera frame (x right, y down, z forward) to clip space such that NDC y = 2 v / height - 1:
/// framebuffer row r then holds picture row r (no flip on read-back). Depth maps [near, far] to
/// [-1, 1]; w_clip = z_camera, so a fragment's gl_FragCoord.w is 1 / z. Column-major, as GL
/// expects.
inline Eigen::Matrix4f world_to_clip(const core::Pinhole& cam, const core::Pose& T_world_cam,
                                     double near_m, double far_m) {
  const double W = cam.width, H = cam.height, n = near_m, f = far_m;
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2.0 * cam.fx / W;
  P(0, 2) = 2.0 * cam.cx / W - 1.0;
  P(1, 1) = 2.0 * cam.fy / H;
  P(1, 2) = 2.0 * cam.cy / H - 1.0;
  P(2, 2) = (f + n) / (f - n);
  P(2, 3) = -2.0 * f * n / (f - n);
  P(3, 2) = 1.0;
  Eigen::Matrix4d V = Eigen::Matrix4d::Identity();
  V.topLeftCorner<3, 3>() = T_world_cam.R.transpose();
  V.topRightCorner<3, 1>() = -(T_world_cam.R.transpose() * T_world_cam.t);
  return (P * V).cast<float>();
}

}  // namespace hd::render::gl
