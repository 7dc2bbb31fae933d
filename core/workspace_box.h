#pragma once
// The teleoperator workspace: the axis-aligned box (world frame) the robot can reach.

#include <Eigen/Core>

namespace hd::core {

/// Axis-aligned box in world coordinates, metres. A flat box (min == max on an axis) is valid;
/// min > max on any axis, or a non-finite corner, is not.
struct WorkspaceBox {
  Eigen::Vector3d min_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_m = Eigen::Vector3d::Zero();

  bool valid() const {
    return min_m.allFinite() && max_m.allFinite() && (min_m.array() <= max_m.array()).all();
  }
};

}  // namespace hd::core
