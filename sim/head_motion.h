#pragma once
// The operator's head motion of a scene as the mock pose source's ScriptedMotion.

#include "drivers/mock/mock_pose_source.h"
#include "sim/scene/scene.h"

namespace hd::sim {

/// A CSV trajectory (replayed from its first sample) or the keyframes: position linear and
/// orientation slerped between keyframes, eased in and out (raised cosine) when `smooth`, held
/// before the first and after the last. Throws std::runtime_error for an unreadable CSV.
drivers::ScriptedMotion make_head_motion(const SceneHead& head);

}  // namespace hd::sim
