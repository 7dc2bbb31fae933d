#pragma once
// E(p_c, p_o, P_c, P_o, d, X): how far from its true place the video shows a world point.

#include <Eigen/Core>
#include <optional>

#include "core/view_setup.h"

namespace hd::core {

/// E(X) = |proj_o(X) - proj_o(X'')| in virtual-screen pixels, X'' the point of the plane z_c = d
/// on the real camera's ray through X (DESIGN.md 3).
///   nullopt: X not in front of both cameras (z <= near in either), X not finite, or invalid setup;
///   +inf:    X'' not in front of the virtual camera (its z_o <= near).
std::optional<double> reprojection_error(const ViewSetup& s, const Eigen::Vector3d& X_world);

}  // namespace hd::core
