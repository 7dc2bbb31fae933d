#include "core/coverage.h"

#include <algorithm>
#include <cmath>

#include "core/video_quad.h"

namespace hd::core {

double coverage(const ViewSetup& s) {
  if (!s.valid()) return 0.0;
  const CameraPair pair(s);
  VideoQuad quad = video_quad_in_virtual(pair);
  clip_to_virtual_frustum(quad, s);
  return coverage_of_clipped_quad(quad, s);
}

double coverage_of_clipped_quad(const VideoQuad& quad, const ViewSetup& s) {
  if (quad.size() < 3) return 0.0;
  // Shoelace on coordinates relative to the first vertex and to the principal point, so a tiny
  // quad far from the origin keeps its digits.
  const Eigen::Vector3d& p0 = quad[0];
  const Eigen::Vector2d q0(s.virt.fx * p0.x() / p0.z(), s.virt.fy * p0.y() / p0.z());
  double area2 = 0.0;
  Eigen::Vector2d prev = Eigen::Vector2d::Zero();
  for (int i = 1; i < quad.size(); ++i) {
    const Eigen::Vector3d& p = quad[i];
    const Eigen::Vector2d q =
        Eigen::Vector2d(s.virt.fx * p.x() / p.z(), s.virt.fy * p.y() / p.z()) - q0;
    area2 += prev.x() * q.y() - q.x() * prev.y();
    prev = q;
  }
  const double c = std::abs(0.5 * area2) / s.virt.area_px();
  return std::isfinite(c) ? std::clamp(c, 0.0, 1.0) : 0.0;
}

}  // namespace hd::core
