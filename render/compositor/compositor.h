#pragma once
// The interface the frame loop draws through: one CPU reference and one OpenGL implementation.

#include "render/compositor/composite_request.h"
#include "render/compositor/compositor_stats.h"
#include "render/compositor/image_rgba8.h"
#include "render/compositor/viewport.h"
#include "render/overlay/overlay.h"

namespace hd::render {

/// Draws one eye's picture (see CompositeRequest for the exact definition of the picture).
///
/// `out` must already be allocated (ImageRgba8::allocate, outside the loop) and contain the
/// request's viewport; only the viewport's pixels are written. After the first draw with a given
/// size, drawing allocates nothing, locks nothing and throws nothing: a malformed request is
/// counted in stats().requests_rejected and leaves `out` untouched.
/// The GL compositor also draws to its window (if it has one) and fills `out` only when
/// `req.read_back` is set. Not thread-safe: one compositor per render thread.
class Compositor {
 public:
  virtual ~Compositor() = default;
  virtual void draw(const CompositeRequest& req, ImageRgba8& out) = 0;
  /// Draws `overlay` (render/overlay/overlay.h) over the picture just drawn in `vp`; same
  /// no-allocation rules as draw (the HUD strip is rendered beforehand by HudStrip::set_text).
  virtual void draw_overlay(const Overlay& overlay, const Viewport& vp, ImageRgba8& out) = 0;
  /// Makes the drawn frame visible (swap buffers); a no-op for the CPU compositor.
  virtual void present() {}
  virtual const CompositorStats& stats() const = 0;
};

}  // namespace hd::render
