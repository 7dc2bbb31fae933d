#include "core/coverage.h"

#include <algorithm>
#include <cmath>

#include "core/video_quad.h"

namespace hd::core {

double coverage(const ViewSetup& s) {
  if (!s.valid()) return 0.0;
  const CameraPair pair(s);
  VideoQuad quad = video_quad_in_virtual(pair);
  quad.clip(HalfSpace3{{0.0, 0.0, 1.0}, -s.near_m});
  // A convex polygon in front of the camera projects to a convex polygon.
  ConvexPolygon<2, 16> img;
  for (int i = 0; i < quad.size(); ++i) img.push_back(s.virt.project(quad[i]));
  const double w = s.virt.width;
  const double h = s.virt.height;
  img.clip(HalfSpace2{{1.0, 0.0}, 0.0});
  img.clip(HalfSpace2{{-1.0, 0.0}, w});
  img.clip(HalfSpace2{{0.0, 1.0}, 0.0});
  img.clip(HalfSpace2{{0.0, -1.0}, h});
  const double c = std::abs(img.signed_area()) / s.virt.area_px();
  return std::isfinite(c) ? std::clamp(c, 0.0, 1.0) : 0.0;
}

}  // namespace hd::core
