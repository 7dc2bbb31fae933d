#pragma once
// The video quad: the real image rectangle placed on the projection plane z_c = d, expressed in
// the virtual camera frame. Coverage and the update region both start from it.

#include "core/camera_pair.h"
#include "core/convex_polygon.h"

namespace hd::core {

/// 4 corners plus one vertex per clip plane used by callers (near + 4 frustum sides).
using VideoQuad = ConvexPolygon<3, 12>;

/// Corners (0,0), (w,0), (w,h), (0,h) of the real image on z_c = d, in the virtual frame.
inline VideoQuad video_quad_in_virtual(const CameraPair& pair) {
  const ViewSetup& s = pair.setup();
  const double w = s.real.width;
  const double h = s.real.height;
  const Eigen::Vector2d corners[4] = {{0.0, 0.0}, {w, 0.0}, {w, h}, {0.0, h}};
  VideoQuad q;
  for (const auto& c : corners) q.push_back(pair.virt_from_real(s.real.ray(c) * s.d_m));
  return q;
}

/// Clips the quad (virtual frame) by the virtual frustum: z_o >= near and the 4 image sides.
/// Clipping in 3D, before projecting, keeps coordinates bounded for huge d or grazing views.
inline void clip_to_virtual_frustum(VideoQuad& quad, const ViewSetup& s) {
  const Pinhole& k = s.virt;
  const double w = k.width;
  const double h = k.height;
  quad.clip(HalfSpace3{{0.0, 0.0, 1.0}, -s.near_m});
  quad.clip(HalfSpace3{{k.fx, 0.0, k.cx}, 0.0}.normalized());
  quad.clip(HalfSpace3{{-k.fx, 0.0, w - k.cx}, 0.0}.normalized());
  quad.clip(HalfSpace3{{0.0, k.fy, k.cy}, 0.0}.normalized());
  quad.clip(HalfSpace3{{0.0, -k.fy, h - k.cy}, 0.0}.normalized());
}

}  // namespace hd::core
