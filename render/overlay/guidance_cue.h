#pragma once
// When only the synthetic view is usable: where the operator should move to get video back.

#include <Eigen/Core>
#include <array>
#include <span>

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::render {

/// A calibrated camera as guidance sees it.
struct GuidanceCamera {
  core::Pinhole p_c;
  core::Pose T_world_real;
  double d_m = 1.0;  ///< its projection plane distance (the ghost frustum is drawn to it)
};

/// What a renderer needs to draw an arrow and a ghost frustum toward the nearest camera pose.
struct GuidanceCue {
  bool active = false;
  int camera = -1;
  double distance_m = 0.0;    ///< eye centre to camera centre
  double rotation_rad = 0.0;  ///< angle between eye and camera orientation
  /// Unit direction in the eye's image (x right, y down) from the image centre toward where the
  /// operator should move/look: toward the camera centre's projection when the camera is more
  /// than `position_tolerance_m` away, else toward the camera's view centre (a pure rotation).
  Eigen::Vector2d direction_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d anchor_px = Eigen::Vector2d::Zero();  ///< arrow start: the eye image centre
  /// The target in the eye image (camera centre, or view centre for a rotation); valid only
  /// when `target_in_front` (otherwise the target is behind the eye: turn around).
  Eigen::Vector2d target_px = Eigen::Vector2d::Zero();
  bool target_in_front = false;
  /// Ghost frustum: camera centre then the four image corners on its plane z_c = d (world).
  std::array<Eigen::Vector3d, 5> frustum_world{};
};

struct GuidanceParams {
  double metres_per_radian = 0.3;  ///< how "near" weighs rotation against translation
  double position_tolerance_m = 0.02;
};

/// The camera pose nearest to the eye (distance + metres_per_radian * rotation angle) and the cue
/// toward it. No cameras: inactive cue. No allocation.
GuidanceCue guidance_toward_nearest(const core::Pinhole& eye, const core::Pose& T_world_eye,
                                    std::span<const GuidanceCamera> cameras,
                                    GuidanceParams params = {});

}  // namespace hd::render
