#pragma once
// Where the operator's tracked space sits in the remote workspace: the tracker-to-workspace
// transform, the re-centre key and tracker reference-frame resets. Pure logic: no threads, no
// clocks, no allocation.

#include <Eigen/Core>
#include <cstdint>

#include "core/pose.h"
#include "drivers/pose_source.h"

namespace hd::station {

/// Conventions (DESIGN.md "Conventions"; docs/tracking.md):
///  - Every pose is "child to parent": T_world_head maps head-frame points to the workspace
///    (world) frame, X_world = R X_head + t; the head frame has camera axes (x right, y down,
///    z forward).
///  - T_world_head = T_world_tracker * T_tracker_head. T_world_tracker starts as the configured
///    transform and is changed only by recentre(), a tracker reset, or restore_configured().
///  - "Up" is a unit vector in the world frame (default -y: the workspace uses camera axes, y
///    down). Heading (yaw) is the angle of the head's forward axis (its z) projected onto the
///    plane normal to up, measured about up; where forward is within ~0.06 deg of vertical the
///    projection of up x (head x axis) is used instead (the yaw that makes roll zero there).
///  - recentre() left-multiplies T_world_tracker by a rotation about up plus a translation, so
///    the angle between any head axis and up -- pitch and roll relative to gravity -- is kept
///    exactly; only heading and position move.
struct TrackerAlignmentConfig {
  core::Pose T_world_tracker;  ///< configured placement of the tracker frame in the workspace
  core::Pose T_world_home;     ///< where recentre() puts the head (position and heading)
  Eigen::Vector3d up_world{0.0, -1.0, 0.0};  ///< workspace up (any length > 0; normalised)

  /// Throws std::invalid_argument naming the bad field (pose not a rotation, non-finite, zero up).
  void validate() const;
};

/// Maps tracker samples into the workspace, in sample order.
///
/// Resets: the tracker bumps PoseSample::reset_counter when its own reference frame jumps (HID
/// discontinuity counter, reconnect). On the first sample with a new counter, T_world_tracker is
/// re-solved so that sample's world pose equals the last world pose before the reset:
///   T_world_tracker' = T_world_head(last before) * T_tracker_head(first after)^-1.
/// The head's real motion between those two samples (one sample period) is absorbed into the new
/// frame; nothing larger appears on screen. A reset before any valid sample just adopts the new
/// counter. Angular velocity is in the head frame and passes through unchanged.
class TrackerAlignment {
 public:
  /// Throws std::invalid_argument (via config.validate()) for a bad configuration.
  explicit TrackerAlignment(const TrackerAlignmentConfig& config);

  /// Maps one sample (in order). On success `out` is `in` with T_tracker_head replaced by
  /// T_world_head (the output's "tracker frame" is the workspace) and reset_counter replaced by
  /// world_jumps(), so a consumer's PoseHistory restarts its prediction after a deliberate
  /// re-centre but not after a tracker reset that alignment made seamless.
  /// Returns false (out untouched, counted in rejected()) for a pose that is not finite or not a
  /// rotation; such a sample changes nothing.
  bool align(const drivers::PoseSample& in, drivers::PoseSample& out);

  /// The world pose of a tracker pose under the current T_world_tracker (no state change).
  core::Pose to_world(const core::Pose& T_tracker_head) const {
    return T_world_tracker_ * T_tracker_head;
  }

  /// Re-places the tracker frame so `current` lands on `T_world_home` in position and heading,
  /// keeping its pitch/roll. A reset pending in `current` is handled first. Returns false (and
  /// changes nothing) for an invalid sample or home pose.
  bool recentre(const drivers::PoseSample& current, const core::Pose& T_world_home);
  bool recentre(const drivers::PoseSample& current) {
    return recentre(current, config_.T_world_home);
  }

  /// Back to the configured T_world_tracker (counts as a world jump).
  void restore_configured();

  const core::Pose& T_world_tracker() const { return T_world_tracker_; }
  const TrackerAlignmentConfig& config() const { return config_; }
  uint64_t tracker_resets() const { return tracker_resets_; }  ///< reset_counter changes seen
  uint64_t recentres() const { return recentres_; }
  uint32_t world_jumps() const { return world_jumps_; }  ///< recentres + restores
  uint64_t rejected() const { return rejected_; }

  /// Heading of a world orientation about `up` (unit), in (-pi, pi], relative to a fixed
  /// horizontal reference; only differences matter. Exposed for tests.
  static double heading_rad(const Eigen::Matrix3d& R_world_head, const Eigen::Vector3d& up);

 private:
  /// Re-solves T_world_tracker if `s` carries a new reset_counter.
  void follow_reset(const drivers::PoseSample& s);

  TrackerAlignmentConfig config_;
  core::Pose T_world_tracker_;
  core::Pose last_world_head_;
  bool have_last_ = false;
  uint32_t reset_counter_ = 0;
  bool seen_counter_ = false;
  uint64_t tracker_resets_ = 0;
  uint64_t recentres_ = 0;
  uint32_t world_jumps_ = 0;
  uint64_t rejected_ = 0;
};

}  // namespace hd::station
