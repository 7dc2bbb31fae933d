#pragma once
// What is drawn over one eye's composited picture: the guidance cue and the HUD strip.

#include <array>
#include <cstdint>

#include "core/pinhole.h"
#include "core/pose.h"
#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"

namespace hd::render {

/// One eye's overlay, for one frame. Plain data; `hud` is borrowed and must outlive the draw.
///
/// Drawn into the eye's viewport, over the composited picture, in this order:
///  - when `cue.active`: the ghost frustum of the camera the cue points to (its centre joined to
///    the four image corners on its plane z_c = d, and the rectangle of those corners), each of
///    the 8 edges clipped in 3D to the eye's near plane z_eye >= near_m, projected with `eye`
///    and clipped to the viewport, as 1-px lines in `frustum_rgb`;
///  - when `cue.active`: the arrow from the viewport centre along cue.direction_px (a third of
///    the smaller viewport side, with a head), `arrow_rgb`, 2r+1 px thick (r = side / 150, 1..4);
///  - when `hud` is set and holds text: the strip alpha-blended at the viewport's top-left.
/// Everything is computed by overlay_geometry(); the CPU painter and the GL compositor only
/// rasterise what it returns, so both draw the same lines.
struct Overlay {
  GuidanceCue cue;    ///< the cue as seen from this eye
  core::Pinhole eye;  ///< the eye's intrinsics (eye.width x eye.height = the viewport's size)
  core::Pose T_world_eye;
  double near_m = 0.05;
  const HudStrip* hud = nullptr;
  std::array<uint8_t, 3> frustum_rgb{0, 255, 255};
  std::array<uint8_t, 3> arrow_rgb{255, 220, 0};

  bool draws_hud() const { return hud != nullptr && !hud->empty(); }
  bool empty() const { return !cue.active && !draws_hud(); }
};

}  // namespace hd::render
