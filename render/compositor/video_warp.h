#pragma once
// The video view as a plane-induced homography: eye pixel -> real camera pixel.

#include <Eigen/Core>

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::render {

/// The real frame, projected onto the plane z_c = d_m of the real camera, seen by the eye.
///
/// For an eye pixel p = (u, v, 1) (continuous coordinates; a pixel centre is (x+0.5, y+0.5)):
///   h = H p is the real pixel in homogeneous form, q = (h0 / h2, h1 / h2);
///   1 / z_eye = inv_depth.dot(p) is the inverse depth of the plane point seen through p.
/// H is scaled so that h2 = d_m / z_eye: h2 > 0 exactly when the plane point is in front of the
/// eye (core's virtual_to_real_homography is the same map up to scale).
struct VideoWarp {
  bool usable = false;  ///< false: eye on the plane, d_m <= 0, or invalid input: no video at all
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d inv_depth = Eigen::Vector3d::Zero();

  static VideoWarp make(const core::Pinhole& eye, const core::Pose& T_world_eye,
                        const core::Pinhole& real, const core::Pose& T_world_real, double d_m);
};

}  // namespace hd::render
