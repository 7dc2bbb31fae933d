#include "render/overlay/overlay_geometry.h"

#include <algorithm>
#include <cmath>

namespace hd::render {

bool clip_to_half_space(Eigen::Vector3d& p0, Eigen::Vector3d& p1, const Eigen::Vector3d& n,
                        double c) {
  if (!p0.allFinite() || !p1.allFinite() || !n.allFinite() || !std::isfinite(c)) return false;
  const double f0 = n.dot(p0) + c, f1 = n.dot(p1) + c;
  const bool in0 = f0 >= 0.0, in1 = f1 >= 0.0;
  if (in0 && in1) return true;
  if (!in0 && !in1) return false;
  // Exactly one end is outside: move it to the crossing (f0 != f1 here).
  const double t = f0 / (f0 - f1);
  (in0 ? p1 : p0) = p0 + t * (p1 - p0);
  return true;
}

bool clip_to_near_plane(Eigen::Vector3d& p0, Eigen::Vector3d& p1, double near_m) {
  if (!clip_to_half_space(p0, p1, Eigen::Vector3d::UnitZ(), -near_m)) return false;
  // The crossing may round a hair below the plane: put it on the plane.
  p0.z() = std::max(p0.z(), near_m);
  p1.z() = std::max(p1.z(), near_m);
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
  const core::Pinhole& k = o.eye;
  if (!k.valid() || !o.T_world_eye.valid() || !(o.near_m > 0.0)) return;
  std::array<Eigen::Vector3d, 5> p;
  for (std::size_t i = 0; i < 5; ++i) p[i] = o.T_world_eye.to_camera(o.cue.frustum_world[i]);
  // The eye's side planes, 1 px outside the image: u >= -1, u <= W + 1, v >= -1, v <= H + 1
  // with u = fx x / z + cx, i.e. fx x + (cx + 1) z >= 0 and so on (z > 0 after the near clip).
  const double u0 = -1.0, u1 = k.width + 1.0, v0 = -1.0, v1 = k.height + 1.0;
  const Eigen::Vector3d side_n[4] = {{k.fx, 0.0, k.cx - u0},
                                     {-k.fx, 0.0, u1 - k.cx},
                                     {0.0, k.fy, k.cy - v0},
                                     {0.0, -k.fy, v1 - k.cy}};
  // Centre to each corner, then the far rectangle.
  constexpr int kEdges[8][2] = {{0, 1}, {0, 2}, {0, 3}, {0, 4}, {1, 2}, {2, 3}, {3, 4}, {4, 1}};
  const Eigen::Vector2d origin(vp.x, vp.y);
  for (int e = 0; e < 8; ++e) {
    Eigen::Vector3d a = p[static_cast<std::size_t>(kEdges[e][0])];
    Eigen::Vector3d b = p[static_cast<std::size_t>(kEdges[e][1])];
    if (!clip_to_near_plane(a, b, o.near_m)) continue;
    bool visible = true;
    for (const Eigen::Vector3d& n : side_n) visible = visible && clip_to_half_space(a, b, n, 0.0);
    if (!visible) continue;
    const int before = out.count;
    push(out, origin + k.project(a), origin + k.project(b), vp, o.frustum_rgb);
    if (out.count > before) out.segment[static_cast<std::size_t>(before)].edge = e;
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
