#include "recon/stereo_rig.h"

#include <string>

namespace hd::recon {

cv::Matx33d StereoRig::R_right_left() const {
  const Eigen::Matrix3d R = T_world_right.R.transpose() * T_world_left.R;
  cv::Matx33d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = R(i, j);
  return out;
}

cv::Vec3d StereoRig::T_right_left() const {
  const Eigen::Vector3d T = T_world_right.R.transpose() * (T_world_left.t - T_world_right.t);
  return {T.x(), T.y(), T.z()};
}

void StereoRig::check(double min_baseline_m) const {
  if (!left.valid()) throw RigError("left camera: invalid intrinsics (focal lengths, image size)");
  if (!right.valid())
    throw RigError("right camera: invalid intrinsics (focal lengths, image size)");
  if (!T_world_left.valid(1e-4)) throw RigError("left camera: pose is not a rigid transform");
  if (!T_world_right.valid(1e-4)) throw RigError("right camera: pose is not a rigid transform");
  if (!(baseline_m() >= min_baseline_m))
    throw RigError("the cameras are " + std::to_string(baseline_m()) +
                   " m apart: a stereo pair needs a baseline of at least " +
                   std::to_string(min_baseline_m) + " m");
}

}  // namespace hd::recon
