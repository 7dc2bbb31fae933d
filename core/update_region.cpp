#include "core/update_region.h"

#include <algorithm>
#include <cmath>

#include "core/video_quad.h"

namespace hd::core {

std::optional<PixelRect> update_region(const ViewSetup& s) {
  if (!s.valid()) return std::nullopt;
  const CameraPair pair(s);
  VideoQuad quad = video_quad_in_virtual(pair);
  clip_to_virtual_frustum(quad, s);
  return region_of_clipped_quad(quad, pair);
}

std::optional<PixelRect> region_of_clipped_quad(const VideoQuad& quad, const CameraPair& pair) {
  const ViewSetup& s = pair.setup();
  if (quad.empty()) return std::nullopt;
  PixelRect r{INFINITY, INFINITY, -INFINITY, -INFINITY};
  const Pinhole& kr = s.real;
  for (int i = 0; i < quad.size(); ++i) {
    // Every vertex lies on z_c = d, where the real projection is affine in x and y.
    const Eigen::Vector3d X_r = pair.real_from_virt(quad[i]);
    const double u = kr.fx * X_r.x() / s.d_m + kr.cx;
    const double v = kr.fy * X_r.y() / s.d_m + kr.cy;
    r.u_min = std::min(r.u_min, u);
    r.u_max = std::max(r.u_max, u);
    r.v_min = std::min(r.v_min, v);
    r.v_max = std::max(r.v_max, v);
  }
  const double rw = kr.width;
  const double rh = kr.height;
  r.u_min = std::clamp(r.u_min, 0.0, rw);
  r.u_max = std::clamp(r.u_max, 0.0, rw);
  r.v_min = std::clamp(r.v_min, 0.0, rh);
  r.v_max = std::clamp(r.v_max, 0.0, rh);
  if (!(std::isfinite(r.u_min) && std::isfinite(r.u_max) && std::isfinite(r.v_min) &&
        std::isfinite(r.v_max)))
    return std::nullopt;
  return r;
}

}  // namespace hd::core
