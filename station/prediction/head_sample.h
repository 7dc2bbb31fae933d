#pragma once
// One validated head pose measurement, in the form the predictors consume.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace hd::station {

/// A head pose at one instant on the station's CLOCK_MONOTONIC time line.
struct HeadSample {
  int64_t t_ns = 0;
  Eigen::Quaterniond q_world_head = Eigen::Quaterniond::Identity();  ///< head axes -> tracker
  Eigen::Vector3d p_world_m = Eigen::Vector3d::Zero();               ///< head centre
  Eigen::Vector3d omega_head_rad_s = Eigen::Vector3d::Zero();        ///< gyro, head frame (if any)
  bool has_omega = false;
  bool has_position = false;
};

}  // namespace hd::station
