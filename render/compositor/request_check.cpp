#include "render/compositor/request_check.h"

#include <cmath>
#include <cstddef>

namespace hd::render {

namespace {
bool finite_positive(double x) {
  return std::isfinite(x) && x > 0.0;
}
}  // namespace

bool request_drawable(const CompositeRequest& r, const ImageRgba8& out) {
  const Viewport& vp = r.viewport;
  if (vp.x < 0 || vp.y < 0 || vp.width <= 0 || vp.height <= 0) return false;
  if (vp.x + vp.width > out.width || vp.y + vp.height > out.height) return false;
  if (out.stride_bytes < 4 * out.width || out.stride_bytes % 4 != 0) return false;
  if (out.data.size() <
      static_cast<std::size_t>(out.stride_bytes) * static_cast<std::size_t>(out.height)) {
    return false;
  }
  if (r.eye.width != vp.width || r.eye.height != vp.height || !r.eye.valid()) return false;
  if (!r.T_world_eye.valid()) return false;
  return finite_positive(r.near_m) && std::isfinite(r.far_m) && r.far_m > r.near_m;
}

bool video_usable(const CompositeRequest& r) {
  const drivers::Frame* f = r.video;
  if (f->format != drivers::PixelFormat::kRgba8 || f->width <= 0 || f->height <= 0) return false;
  if (f->width != r.real.width || f->height != r.real.height) return false;
  if (f->stride_bytes < 4 * f->width || f->stride_bytes % 4 != 0) return false;
  if (f->data.size() <
      static_cast<std::size_t>(f->stride_bytes) * static_cast<std::size_t>(f->height)) {
    return false;
  }
  const core::PixelRect& g = r.region;
  if (!std::isfinite(g.u_min) || !std::isfinite(g.u_max) || !std::isfinite(g.v_min) ||
      !std::isfinite(g.v_max)) {
    return false;
  }
  return r.real.valid() && r.T_world_real.valid() && finite_positive(r.d_m);
}

}  // namespace hd::render
