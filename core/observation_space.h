#pragma once
// W: the virtual viewing frustum clipped to the workspace and to the real camera's front.

#include <array>

#include "core/convex_polyhedron.h"
#include "core/view_setup.h"

namespace hd::core {

/// The virtual camera's frustum as 5 world-frame half-spaces: u >= 0, u <= width, v >= 0,
/// v <= height, z_o >= near (no far plane: the workspace bounds it).
std::array<HalfSpace3, 5> virtual_frustum_world(const ViewSetup& s);

/// The clipping tolerance in metres for a setup: a few ulps of its largest coordinate, so flat
/// workspaces and vertices on a near plane survive rounding.
double geometry_tolerance_m(const ViewSetup& s);

/// The 6 world-frame half-spaces that cut the workspace box into W: the virtual frustum's 5 and
/// the real camera's front z_c >= near.
std::array<HalfSpace3, 6> observation_space_cuts(const ViewSetup& s);

/// W = virtual frustum (4 sides + near) ∩ workspace box ∩ {z_c >= near} (DESIGN.md 2), in world
/// coordinates. Empty for an invalid setup. No allocation.
ConvexPolyhedron observation_space(const ViewSetup& s);

}  // namespace hd::core
