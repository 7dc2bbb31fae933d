#pragma once
// A small built-in workspace model for demos, tests and benchmarks, and a camera frame of it.

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/frame.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::render {

/// A 2 m x 2 m table top (checker texture) at y = +0.4 m below the world origin, a back wall at
/// z = 2.2 m (colour gradient), and a 0.3 m box standing on the table (two-tone faces). World
/// frame as the cameras' (x right, y down, z forward), so an identity pose looks at the wall.
/// Allocates: call once, outside the render loop.
SyntheticScene make_demo_scene();

/// Fills `frame` (allocated to camera.width x camera.height RGBA8 if its size differs) with what
/// `camera` at `T_world_camera` sees of `scene` -- rendered by the CPU reference -- with the
/// colours shifted by `tint` so video and model are told apart, plus a fine stripe pattern on
/// the wall so the video carries detail the model does not. This is the mock camera's picture.
void render_demo_frame(const SyntheticScene& scene, const core::Pinhole& camera,
                       const core::Pose& T_world_camera, int tint, drivers::Frame& frame);

}  // namespace hd::render
