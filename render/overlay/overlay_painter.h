#pragma once
// The CPU painter of an overlay: what the CPU compositor's draw_overlay runs.

#include "render/compositor/image_rgba8.h"
#include "render/compositor/viewport.h"
#include "render/overlay/overlay.h"
#include "render/overlay/overlay_geometry.h"

namespace hd::render {

/// Paints `overlay` (see overlay.h) into `out` inside `vp`; pixels outside the viewport (and
/// outside `out`) are never written. Lines are 1 px, not anti-aliased: a line lights, for each
/// pixel centre on its major axis within [start, end), the pixel its centre line passes through
/// (close to GL's diamond-exit rule). The HUD strip is blended as
/// out = (a * strip + (255 - a) * out + 127) / 255 per colour channel, out's alpha unchanged.
/// No allocation.
void paint_overlay(const Overlay& overlay, const Viewport& vp, ImageRgba8& out);

/// The line rasteriser paint_overlay uses (exposed for tests).
void paint_segment(const OverlaySegment& s, const Viewport& vp, ImageRgba8& out);

/// The HUD blend paint_overlay uses (exposed for tests).
void blit_hud(const ImageRgba8& strip, const Viewport& vp, ImageRgba8& out);

}  // namespace hd::render
