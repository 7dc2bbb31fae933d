#pragma once
// Draws a guidance cue as an arrow into one eye's viewport (CPU, no allocation).

#include "render/compositor/image_rgba8.h"
#include "render/compositor/viewport.h"
#include "render/selection/guidance_cue.h"

namespace hd::render {

/// An arrow from the viewport centre along cue.direction_px, a third of the smaller viewport
/// side long, with a head; clipped to the viewport. Inactive cue: nothing drawn.
void draw_guidance_arrow(const GuidanceCue& cue, const Viewport& vp, ImageRgba8& out);

}  // namespace hd::render
