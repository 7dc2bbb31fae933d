#pragma once
// The plane-induced homography the compositor uses to draw the video quad.

#include <Eigen/Core>

#include "core/view_setup.h"

namespace hd::core {

/// Maps a virtual pixel (u, v, 1) to the real pixel (homogeneous) seen through the plane z_c = d:
///   H = K_c ((d - t_z) I + t e_z^T) R K_o^-1,   (R, t) = T_real_virt.
/// Divide by the third coordinate; it is positive exactly when the virtual ray meets the plane in
/// front of the virtual camera (the sign of H is chosen so). A virtual camera on the plane gives a
/// rank-1 H (the plane is seen edge-on). Invalid setup: the zero matrix.
Eigen::Matrix3d virtual_to_real_homography(const ViewSetup& s);

}  // namespace hd::core
