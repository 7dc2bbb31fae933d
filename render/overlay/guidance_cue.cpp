#include "render/overlay/guidance_cue.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

namespace hd::render {

GuidanceCue guidance_toward_nearest(const core::Pinhole& eye, const core::Pose& T_world_eye,
                                    std::span<const GuidanceCamera> cameras,
                                    GuidanceParams params) {
  GuidanceCue cue;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const core::Pose& P = cameras[i].T_world_real;
    if (!P.valid()) continue;
    const double dist = (P.t - T_world_eye.t).norm();
    const double rot = Eigen::AngleAxisd(T_world_eye.R.transpose() * P.R).angle();
    const double cost = dist + params.metres_per_radian * rot;
    if (cost < best) {
      best = cost;
      cue.camera = static_cast<int>(i);
      cue.distance_m = dist;
      cue.rotation_rad = rot;
    }
  }
  if (cue.camera < 0) return cue;
  cue.active = true;
  const GuidanceCamera& cam = cameras[static_cast<std::size_t>(cue.camera)];
  cue.anchor_px = {eye.width * 0.5, eye.height * 0.5};

  // Target in the eye frame: the camera centre, or (already there) the point it looks at.
  const Eigen::Vector3d target_world =
      cue.distance_m > params.position_tolerance_m
          ? cam.T_world_real.t
          : cam.T_world_real.to_world(Eigen::Vector3d(0.0, 0.0, cam.d_m));
  const Eigen::Vector3d v = T_world_eye.to_camera(target_world);
  constexpr double kInFront = 1e-6;
  if (v.z() > kInFront) {
    cue.target_in_front = true;
    cue.target_px = eye.project(v);
    const Eigen::Vector2d d = cue.target_px - cue.anchor_px;
    cue.direction_px = d.norm() > 1e-9 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d::Zero();
  } else {
    // Behind the eye: point sideways toward it (the way to turn); straight behind: turn right.
    const Eigen::Vector2d d(v.x() * eye.fx, v.y() * eye.fy);
    cue.direction_px =
        d.norm() > 1e-12 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d(1.0, 0.0);
  }

  const core::Pinhole& p = cam.p_c;
  cue.frustum_world[0] = cam.T_world_real.t;
  const double corners[4][2] = {{0.0, 0.0},
                                {double(p.width), 0.0},
                                {double(p.width), double(p.height)},
                                {0.0, double(p.height)}};
  for (int k = 0; k < 4; ++k)
    cue.frustum_world[k + 1] =
        cam.T_world_real.to_world(p.ray({corners[k][0], corners[k][1]}) * cam.d_m);
  return cue;
}

}  // namespace hd::render
