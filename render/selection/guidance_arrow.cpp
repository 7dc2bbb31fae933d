#include "render/selection/guidance_arrow.h"

#include <algorithm>
#include <cmath>

namespace hd::render {
namespace {

void dot(ImageRgba8& out, const Viewport& vp, int x, int y, int radius) {
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int px = x + dx, py = y + dy;
      if (px < vp.x || py < vp.y || px >= vp.x + vp.width || py >= vp.y + vp.height) continue;
      if (px >= out.width || py >= out.height || px < 0 || py < 0) continue;
      uint8_t* p = out.pixel(px, py);
      p[0] = 255, p[1] = 220, p[2] = 0, p[3] = 255;
    }
}

void line(ImageRgba8& out, const Viewport& vp, Eigen::Vector2d a, Eigen::Vector2d b, int radius) {
  const double len = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(len)));
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / steps);
    dot(out, vp, static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())), radius);
  }
}

}  // namespace

void draw_guidance_arrow(const GuidanceCue& cue, const Viewport& vp, ImageRgba8& out) {
  if (!cue.active || !cue.direction_px.allFinite() || cue.direction_px.norm() < 0.5) return;
  const Eigen::Vector2d dir = cue.direction_px.normalized();
  const Eigen::Vector2d c(vp.x + vp.width * 0.5, vp.y + vp.height * 0.5);
  const double len = std::min(vp.width, vp.height) / 3.0;
  const Eigen::Vector2d tip = c + dir * len;
  const int radius = std::max(1, std::min(vp.width, vp.height) / 150);
  line(out, vp, c, tip, radius);
  const Eigen::Vector2d back = -dir * (len * 0.3);
  const Eigen::Vector2d side(-dir.y(), dir.x());
  line(out, vp, tip, tip + back + side * (len * 0.2), radius);
  line(out, vp, tip, tip + back - side * (len * 0.2), radius);
}

}  // namespace hd::render
