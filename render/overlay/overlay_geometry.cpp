#include "render/overlay/overlay_geometry.h"

#include <algorithm>
#include <cmath>

namespace hd::render {

bool clip_to_near_plane(Eigen::Vector3d& p0, Eigen::Vector3d& p1, double near_m) {
  if (!p0.allFinite() || !p1.allFinite() || !std::isfinite(near_m)) return false;
  const bool in0 = p0.z() >= near_m, in1 = p1.z() >= near_m;
  if (in0 && in1) return true;
  if (!in0 && !in1) return false;
  // Exactly one end is behind: move it to the crossing (the z difference is nonzero here).
  const double t = (near_m - p0.z()) / (p1.z() - p0.z());
  Eigen::Vector3d x = p0 + t * (p1 - p0);
  x.z() = near_m;  // no rounding below the plane
  (in0 ? p1 : p0) = x;
  return true;
}

bool clip_to_rect(Eigen::Vector2d& a, Eigen::Vector2d& b, double x0, double y0, double x1,
                  double y1) {
  if (!a.allFinite() || !b.allFinite()) return false;
  const Eigen::Vector2d d = b - a;
  double t0 = 0.0, t1 = 1.0;
  // Each boundary as p * t <= q.
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - x0, x1 - a.x(), a.y() - y0, y1 - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0.0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
    if (t0 > t1) return false;
  }
  const Eigen::Vector2d a0 = a;
  a = a0 + t0 * d;
  b = a0 + t1 * d;
  return true;
}

namespace {

void push(OverlaySegments& out, Eigen::Vector2d a, Eigen::Vector2d b, const Viewport& vp,
          const std::array<uint8_t, 3>& rgb) {
  if (out.count >= OverlaySegments::kCapacity) return;
  if (!clip_to_rect(a, b, vp.x, vp.y, double(vp.x) + vp.width, double(vp.y) + vp.height)) return;
  out.segment[static_cast<std::size_t>(out.count++)] = {a, b, rgb};
}

void frustum(const Overlay& o, const Viewport& vp, OverlaySegments& out) {
  if (!o.eye.valid() || !o.T_world_eye.valid() || !(o.near_m > 0.0)) return;
  std::array<Eigen::Vector3d, 5> p;
  for (std::size_t i = 0; i < 5; ++i) p[i] = o.T_world_eye.to_camera(o.cue.frustum_world[i]);
  // Centre to each corner, then the far rectangle.
  constexpr int kEdges[8][2] = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 2}, {2, 3}, {3, 4}, {4, 1}};
  const Eigen::Vector2d origin(vp.x, vp.y);
  for (const auto& e : kEdges) {
    Eigen::Vector3d a = p[static_cast<std::size_t>(e[0])], b = p[static_cast<std::size_t>(e[1])];
    if (!clip_to_near_plane(a, b, o.near_m)) continue;
    push(out, origin + o.eye.project(a), origin + o.eye.project(b), vp, o.frustum_rgb);
  }
}

void arrow(const Overlay& o, const Viewport& vp, OverlaySegments& out) {
  const Eigen::Vector2d dir_in = o.cue.direction_px;
  if (!dir_in.allFinite() || dir_in.norm() < 0.5) return;
  const Eigen::Vector2d dir = dir_in.normalized();
  const Eigen::Vector2d c(vp.x + vp.width * 0.5, vp.y + vp.height * 0.5);
  const int side = std::min(vp.width, vp.height);
  const double len = side / 3.0;
  const int r = std::clamp(side / 150, 1, 4);
  const Eigen::Vector2d tip = c + dir * len;
  const Eigen::Vector2d back = -dir * (len * 0.3);
  const Eigen::Vector2d across(-dir.y(), dir.x());
  const Eigen::Vector2d strokes[3][2] = {
      {c, tip}, {tip, tip + back + across * (len * 0.2)}, {tip, tip + back - across * (len * 0.2)}};
  for (const auto& s : strokes) {
    // Thickness from parallel 1-px lines offset along the stroke's minor axis, so that GL_LINES
    // (1 px wide in a core profile) draws exactly the same set.
    const Eigen::Vector2d d = s[1] - s[0];
    const Eigen::Vector2d step =
        std::abs(d.x()) >= std::abs(d.y()) ? Eigen::Vector2d(0, 1) : Eigen::Vector2d(1, 0);
    for (int k = -r; k <= r; ++k) push(out, s[0] + k * step, s[1] + k * step, vp, o.arrow_rgb);
  }
}

}  // namespace

void overlay_geometry(const Overlay& overlay, const Viewport& vp, OverlaySegments& out) {
  out.count = 0;
  out.frustum_count = 0;
  if (!overlay.cue.active || vp.width <= 0 || vp.height <= 0) return;
  frustum(overlay, vp, out);
  out.frustum_count = out.count;
  arrow(overlay, vp, out);
}

}  // namespace hd::render
