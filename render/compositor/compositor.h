#pragma once
// The interface the frame loop draws through: one CPU reference and one OpenGL implementation.

#include "render/compositor/composite_request.h"
#include "render/compositor/compositor_stats.h"
#include "render/compositor/image_rgba8.h"
#include "render/compositor/viewport.h"
#include "render/overlay/overlay.h"

namespace hd::render {

namespace lens {
class LensWarp;
}

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
  /// Prepares the HMD's lens pass (render/lens/): builds the CPU table or the GL mesh, so it may
  /// allocate; call before the loop. nullptr (the default): no lens, nothing is pre-distorted.
  /// `warp` must outlive the compositor's use of it.
  virtual void set_lens(const lens::LensWarp* warp) = 0;
  /// Warps the eyes just drawn (`eyes`, the StereoRig layout) through the lens into `panel` (the
  /// HMD panel's picture, allocated to its size) for R, G and B separately; what present() then
  /// shows. Same no-allocation rules as draw. The GL compositor fills `panel` only when the
  /// frame's draws read back. Without set_lens: nothing happens.
  virtual void predistort(const ImageRgba8& eyes, ImageRgba8& panel) = 0;
  /// Makes the drawn frame visible (swap buffers); a no-op for the CPU compositor.
  virtual void present() {}
  virtual const CompositorStats& stats() const = 0;
};

}  // namespace hd::render
