#pragma once
// A camera pose from yaw and pitch in degrees: how the tests and the benchmark place eyes and
// cameras around the demo workspace (one definition, so their scenes agree).

#include <Eigen/Geometry>
#include <numbers>

#include "core/pose.h"

namespace hd::render {

/// Camera-to-world pose at `t_m` (metres), turned by `yaw_deg` about the world y axis (down),
/// then by `pitch_deg` about the turned x axis: R = Ry(yaw) Rx(pitch). Positive yaw turns the
/// view towards +x (right), positive pitch towards -y (up), as cameras look along +z.
inline core::Pose look_pose(double yaw_deg, double pitch_deg, const Eigen::Vector3d& t_m) {
  const double k = std::numbers::pi / 180.0;
  return {(Eigen::AngleAxisd(yaw_deg * k, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(pitch_deg * k, Eigen::Vector3d::UnitX()))
              .toRotationMatrix(),
          t_m};
}

}  // namespace hd::render
