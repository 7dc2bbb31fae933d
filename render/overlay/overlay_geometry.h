#pragma once
// The lines of an overlay in output pixels: computed once, rasterised by the CPU painter and GL.

#include <Eigen/Core>
#include <array>
#include <cstdint>

#include "render/compositor/viewport.h"
#include "render/overlay/overlay.h"

namespace hd::render {

/// A 2D segment in output-image pixels (continuous coordinates: pixel (x, y) covers
/// [x, x+1] x [y, y+1]), already clipped to its viewport.
struct OverlaySegment {
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  std::array<uint8_t, 3> rgb{};
  int edge = -1;  ///< frustum edge 0..7 (centre to corner 1..4, then the rectangle); -1: arrow
};

/// Fixed capacity: 8 frustum edges plus 3 arrow strokes of up to 9 parallel lines.
struct OverlaySegments {
  static constexpr int kCapacity = 8 + 3 * 9;
  std::array<OverlaySegment, kCapacity> segment{};
  int count = 0;
  int frustum_count = 0;  ///< the first frustum_count segments are frustum edges
};

/// The frustum edges and arrow strokes of `overlay` for viewport `vp` (see overlay.h for what
/// is drawn). Segments entirely behind the eye's near plane or outside the viewport are left
/// out; the others are clipped in 3D at z_eye = near_m before projection (a segment crossing the
/// near plane ends where it crosses it, never wraps through infinity) and to the eye's side
/// planes widened by 1 px (so no projected coordinate is huge and loses precision), then clipped
/// to the viewport rectangle. Inactive cue: no segments. No allocation.
void overlay_geometry(const Overlay& overlay, const Viewport& vp, OverlaySegments& out);

/// Clips the eye-frame segment p0-p1 to z >= near_m in place; false when nothing is left.
bool clip_to_near_plane(Eigen::Vector3d& p0, Eigen::Vector3d& p1, double near_m);

/// Clips the segment p0-p1 to the half-space n . p + c >= 0 in place; false when nothing is left.
bool clip_to_half_space(Eigen::Vector3d& p0, Eigen::Vector3d& p1, const Eigen::Vector3d& n,
                        double c);

/// Clips a 2D segment to [x0, x1] x [y0, y1] in place (Liang-Barsky); false when nothing is left.
bool clip_to_rect(Eigen::Vector2d& a, Eigen::Vector2d& b, double x0, double y0, double x1,
                  double y1);

}  // namespace hd::render
