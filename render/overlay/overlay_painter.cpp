#include "render/overlay/overlay_painter.h"

#include <algorithm>
#include <cmath>

namespace hd::render {

namespace {

struct Clip {
  int x0, y0, x1, y1;  ///< half-open: the viewport inside the image
};

Clip clip_of(const Viewport& vp, const ImageRgba8& out) {
  return {std::max(vp.x, 0), std::max(vp.y, 0), std::min(vp.x + vp.width, out.width),
          std::min(vp.y + vp.height, out.height)};
}

}  // namespace

void paint_segment(const OverlaySegment& s, const Viewport& vp, ImageRgba8& out) {
  const Clip c = clip_of(vp, out);
  if (c.x0 >= c.x1 || c.y0 >= c.y1) return;
  const Eigen::Vector2d d = s.b - s.a;
  if (!d.allFinite()) return;
  const bool x_major = std::abs(d.x()) >= std::abs(d.y());
  const double major_a = x_major ? s.a.x() : s.a.y();
  const double major_d = x_major ? d.x() : d.y();
  if (major_d == 0.0) return;
  const double minor_a = x_major ? s.a.y() : s.a.x();
  const double minor_d = x_major ? d.y() : d.x();
  const double lo = std::min(major_a, major_a + major_d), hi = std::max(major_a, major_a + major_d);
  // Pixel centres i + 0.5 in [lo, hi).
  const int lim_lo = x_major ? c.x0 : c.y0, lim_hi = x_major ? c.x1 : c.y1;
  const int i0 = static_cast<int>(std::clamp(std::ceil(lo - 0.5), double(lim_lo), double(lim_hi)));
  const int i1 = static_cast<int>(std::clamp(std::ceil(hi - 0.5), double(lim_lo), double(lim_hi)));
  for (int i = i0; i < i1; ++i) {
    const double t = (i + 0.5 - major_a) / major_d;
    const double minor = std::floor(minor_a + t * minor_d);
    if (!(minor >= -1.0 && minor <= 1e9)) continue;
    const int j = static_cast<int>(minor);
    const int x = x_major ? i : j, y = x_major ? j : i;
    if (x < c.x0 || x >= c.x1 || y < c.y0 || y >= c.y1) continue;
    uint8_t* p = out.pixel(x, y);
    p[0] = s.rgb[0];
    p[1] = s.rgb[1];
    p[2] = s.rgb[2];
    p[3] = 255;
  }
}

void blit_hud(const ImageRgba8& strip, const Viewport& vp, ImageRgba8& out) {
  const Clip c = clip_of(vp, out);
  const int w = std::min(strip.width, c.x1 - vp.x), h = std::min(strip.height, c.y1 - vp.y);
  for (int y = std::max(0, c.y0 - vp.y); y < h; ++y) {
    const uint8_t* s = strip.row(y);
    for (int x = std::max(0, c.x0 - vp.x); x < w; ++x) {
      const uint8_t* sp = s + 4 * x;
      const unsigned a = sp[3];
      if (a == 0) continue;
      uint8_t* p = out.pixel(vp.x + x, vp.y + y);
      for (int k = 0; k < 3; ++k)
        p[k] = static_cast<uint8_t>((a * sp[k] + (255u - a) * p[k] + 127u) / 255u);
    }
  }
}

void paint_overlay(const Overlay& overlay, const Viewport& vp, ImageRgba8& out) {
  if (out.empty() || overlay.empty()) return;
  OverlaySegments segs;
  overlay_geometry(overlay, vp, segs);
  for (int i = 0; i < segs.count; ++i)
    paint_segment(segs.segment[static_cast<std::size_t>(i)], vp, out);
  if (overlay.draws_hud()) blit_hud(overlay.hud->image(), vp, out);
}

}  // namespace hd::render
