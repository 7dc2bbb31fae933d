#include "station/tracking/tracker_alignment.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hd::station {

namespace {

bool valid_pose(const core::Pose& p) {
  return p.valid(1e-6);
}

// Re-orthonormalises a product of rotations so rounding does not accumulate over many resets.
core::Pose orthonormalised(const core::Pose& p) {
  return {Eigen::Quaterniond(p.R).normalized().toRotationMatrix(), p.t};
}

}  // namespace

void TrackerAlignmentConfig::validate() const {
  if (!valid_pose(T_world_tracker))
    throw std::invalid_argument(
        "tracker alignment: T_world_tracker is not a finite rigid transform (rotation must be "
        "orthonormal with det +1)");
  if (!valid_pose(T_world_home))
    throw std::invalid_argument(
        "tracker alignment: T_world_home is not a finite rigid transform (rotation must be "
        "orthonormal with det +1)");
  if (!up_world.allFinite() || !(up_world.norm() > 1e-9))
    throw std::invalid_argument("tracker alignment: up_world must be a finite non-zero vector");
}

TrackerAlignment::TrackerAlignment(const TrackerAlignmentConfig& config) : config_(config) {
  config_.validate();
  config_.up_world.normalize();
  T_world_tracker_ = config_.T_world_tracker;
}

double TrackerAlignment::heading_rad(const Eigen::Matrix3d& R_world_head,
                                     const Eigen::Vector3d& up) {
  // A fixed horizontal basis (e1, e2) of the plane normal to up; heading = atan2 in it.
  const Eigen::Vector3d seed =
      std::abs(up.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d e1 = (seed - seed.dot(up) * up).normalized();
  const Eigen::Vector3d e2 = up.cross(e1);
  Eigen::Vector3d f = R_world_head.col(2);
  f -= f.dot(up) * up;
  // Forward within ~1e-3 rad of vertical: heading is gimbal-locked with roll; take the heading
  // that gives zero roll, i.e. forward = up x right (right = head x axis, then horizontal).
  if (f.norm() < 1e-3) {
    Eigen::Vector3d r = R_world_head.col(0);
    r -= r.dot(up) * up;
    f = up.cross(r);
  }
  return std::atan2(f.dot(e2), f.dot(e1));
}

void TrackerAlignment::follow_reset(const drivers::PoseSample& s) {
  if (!seen_counter_) {
    seen_counter_ = true;
    reset_counter_ = s.reset_counter;
    return;
  }
  if (s.reset_counter == reset_counter_) return;
  reset_counter_ = s.reset_counter;
  ++tracker_resets_;
  if (!have_last_) return;  // nothing on screen yet to stay continuous with
  T_world_tracker_ = orthonormalised(last_world_head_ * s.T_tracker_head.inverse());
}

bool TrackerAlignment::align(const drivers::PoseSample& in, drivers::PoseSample& out) {
  if (!valid_pose(in.T_tracker_head)) {
    ++rejected_;
    return false;
  }
  follow_reset(in);
  const core::Pose world = T_world_tracker_ * in.T_tracker_head;
  last_world_head_ = world;
  have_last_ = true;
  out = in;
  out.T_tracker_head = world;
  out.reset_counter = world_jumps_;
  return true;
}

bool TrackerAlignment::recentre(const drivers::PoseSample& current,
                                const core::Pose& T_world_home) {
  if (!valid_pose(current.T_tracker_head) || !valid_pose(T_world_home)) return false;
  follow_reset(current);
  const Eigen::Vector3d& up = config_.up_world;
  const core::Pose world = T_world_tracker_ * current.T_tracker_head;
  const double yaw =
      heading_rad(T_world_home.R, up) - heading_rad(world.R, up);  // rotate current onto home
  const Eigen::Matrix3d R_fix = Eigen::AngleAxisd(yaw, up).toRotationMatrix();
  // C = (R_fix, c) with C * world placing the head at home: R_fix t_world + c = t_home.
  const core::Pose C{R_fix, T_world_home.t - R_fix * world.t};
  T_world_tracker_ = orthonormalised(C * T_world_tracker_);
  last_world_head_ = T_world_tracker_ * current.T_tracker_head;
  have_last_ = true;
  ++recentres_;
  ++world_jumps_;
  return true;
}

void TrackerAlignment::restore_configured() {
  T_world_tracker_ = config_.T_world_tracker;
  have_last_ = false;  // the next sample defines continuity afresh
  ++world_jumps_;
}

}  // namespace hd::station
