// TrackerAlignment against closed forms: a hand-computed transform, re-centre built from
// yaw/pitch/roll factors, a scripted trajectory whose tracker frame jumps by a known rigid
// transform, and properties over random transforms, trajectories and resets.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "station/tracking/tracker_alignment.h"

namespace {

using hd::core::Pose;
using hd::drivers::PoseSample;
using hd::station::TrackerAlignment;
using hd::station::TrackerAlignmentConfig;

constexpr double kPi = std::numbers::pi;
const Eigen::Vector3d kUp{0.0, -1.0, 0.0};  // workspace: camera axes, y down

Eigen::Matrix3d rot(double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// Head orientation from heading about up, then pitch about the head's x, then roll about its z:
// the factorisation whose first factor re-centre may change and whose other two it must keep.
Eigen::Matrix3d ypr(double yaw, double pitch, double roll) {
  return rot(yaw, kUp) * rot(pitch, Eigen::Vector3d::UnitX()) * rot(roll, Eigen::Vector3d::UnitZ());
}

PoseSample sample(const Pose& T_tracker_head, uint32_t reset_counter = 0, uint64_t seq = 0) {
  PoseSample s;
  s.T_tracker_head = T_tracker_head;
  s.has_position = true;
  s.reset_counter = reset_counter;
  s.sequence = seq;
  return s;
}

double rot_angle(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

TrackerAlignmentConfig config(const Pose& T_world_tracker, const Pose& home = Pose::identity()) {
  TrackerAlignmentConfig c;
  c.T_world_tracker = T_world_tracker;
  c.T_world_home = home;
  c.up_world = kUp;
  return c;
}

TEST(TrackingAlignment, KnownTransformMapsKnownPose) {
  // Tracker frame turned +90 deg about world y and placed at (1, 2, 3). A head at tracker (0,0,1)
  // looking along tracker +z: R_y(90) (0,0,1) = (1,0,0), so world position (2,2,3), looking +x.
  TrackerAlignment a(config({rot(kPi / 2, Eigen::Vector3d::UnitY()), {1.0, 2.0, 3.0}}));
  PoseSample out;
  PoseSample in = sample({Eigen::Matrix3d::Identity(), {0.0, 0.0, 1.0}});
  in.angular_velocity_rad_s = {0.1, -0.2, 0.3};
  in.has_angular_velocity = true;
  in.sequence = 17;
  in.host_timestamp_ns = 123456789;
  ASSERT_TRUE(a.align(in, out));
  EXPECT_NEAR((out.T_tracker_head.t - Eigen::Vector3d(2.0, 2.0, 3.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((out.T_tracker_head.R.col(2) - Eigen::Vector3d(1.0, 0.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((out.T_tracker_head.R.col(1) - Eigen::Vector3d(0.0, 1.0, 0.0)).norm(), 0.0, 1e-12);
  // Head-frame angular velocity and every other field pass through.
  EXPECT_EQ(out.angular_velocity_rad_s, in.angular_velocity_rad_s);
  EXPECT_TRUE(out.has_angular_velocity);
  EXPECT_EQ(out.sequence, 17u);
  EXPECT_EQ(out.host_timestamp_ns, 123456789);
  EXPECT_EQ(out.reset_counter, 0u);
}

TEST(TrackingAlignment, RecentrePutsHeadAtHomePositionAndHeadingKeepingPitchRoll) {
  const Pose T_world_tracker{rot(0.4, {0.2, 1.0, 0.1}), {0.3, -0.1, 0.7}};
  const Pose home{ypr(-0.6, 0.15, -0.05), {0.05, -0.25, 0.4}};
  TrackerAlignment a(config(T_world_tracker, home));
  const double yaw = 1.1, pitch = 0.35, roll = -0.2;
  // The tracker pose whose world orientation is ypr(yaw, pitch, roll), at world (0.9, 0.1, -0.3).
  const Pose world_before{ypr(yaw, pitch, roll), {0.9, 0.1, -0.3}};
  const PoseSample s = sample(T_world_tracker.inverse() * world_before);
  ASSERT_TRUE(a.recentre(s));
  PoseSample out;
  ASSERT_TRUE(a.align(s, out));
  // Closed form: heading becomes home's (-0.6), pitch and roll stay (0.35, -0.2).
  EXPECT_LT(rot_angle(out.T_tracker_head.R, ypr(-0.6, pitch, roll)), 1e-12);
  EXPECT_LT((out.T_tracker_head.t - home.t).norm(), 1e-12);
  EXPECT_EQ(a.recentres(), 1u);
  EXPECT_EQ(out.reset_counter, 1u);  // a deliberate world jump: the predictor restarts
  // The correction is a rotation about up: the angle of every head axis to up is unchanged.
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(out.T_tracker_head.R.col(axis).dot(kUp), world_before.R.col(axis).dot(kUp), 1e-12);
  // Later samples move rigidly with the new frame: a head step of 0.1 m along tracker x moves the
  // world head 0.1 m.
  PoseSample later = s;
  later.T_tracker_head.t += Eigen::Vector3d(0.1, 0.0, 0.0);
  PoseSample out2;
  ASSERT_TRUE(a.align(later, out2));
  EXPECT_NEAR((out2.T_tracker_head.t - out.T_tracker_head.t).norm(), 0.1, 1e-12);
}

TEST(TrackingAlignment, RecentreLookingStraightDownUsesRightAxisForHeading) {
  // Forward along +y (down): heading comes from the right axis. Head right = world +z here;
  // forward-horizontal = up x right = (-y) x z = -x.
  const Pose home{ypr(0.0, 0.0, 0.0), {0.0, 0.0, 0.0}};
  TrackerAlignment a(config(Pose::identity(), home));
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d::UnitZ();  // right
  R.col(2) = Eigen::Vector3d::UnitY();  // forward = down
  R.col(1) = R.col(2).cross(R.col(0));  // y = z x x
  ASSERT_NEAR(R.determinant(), 1.0, 1e-12);
  EXPECT_NEAR(TrackerAlignment::heading_rad(R, kUp),
              TrackerAlignment::heading_rad(ypr(kPi / 2, 0, 0), kUp), 1e-9)
      << "ypr(pi/2) faces -x: the same heading";
  ASSERT_TRUE(a.recentre(sample({R, {1.0, 1.0, 1.0}})));
  PoseSample out;
  ASSERT_TRUE(a.align(sample({R, {1.0, 1.0, 1.0}}), out));
  // Rotated by -pi/2 about up: right becomes +x, forward stays down.
  EXPECT_LT((out.T_tracker_head.R.col(0) - Eigen::Vector3d::UnitX()).norm(), 1e-9);
  EXPECT_LT((out.T_tracker_head.R.col(2) - Eigen::Vector3d::UnitY()).norm(), 1e-9);
  EXPECT_LT(out.T_tracker_head.t.norm(), 1e-12);
}

// A smooth head path in the world: position and orientation as functions of time.
Pose truth_at(double t) {
  return {ypr(0.8 * std::sin(1.3 * t), 0.3 * std::sin(0.7 * t + 0.4), 0.1 * std::cos(2.1 * t)),
          {0.2 * std::sin(t), -0.05 * std::cos(1.7 * t), 0.1 * std::sin(0.5 * t + 1.0)}};
}

TEST(TrackingAlignment, ResetMidTrajectoryLeavesNoJumpLargerThanOneSampleOfMotion) {
  const Pose T_world_F0{rot(0.3, kUp), {0.1, 0.0, -0.2}};
  // After the reset the tracker reports in a frame F1 = F0 * J: turned 40 deg, moved 0.5 m.
  const Pose J{rot(0.7, {0.3, 1.0, -0.2}), {0.5, -0.1, 0.3}};
  const Pose T_world_F1 = T_world_F0 * J;
  TrackerAlignment a(config(T_world_F0));
  constexpr int kN = 400, kReset = 200;
  constexpr double kDt = 0.01;
  std::vector<Pose> out;
  double max_truth_step_m = 0.0, max_truth_step_rad = 0.0;
  double max_raw_step_m = 0.0;
  for (int i = 0; i < kN; ++i) {
    const Pose truth = truth_at(i * kDt);
    const bool after = i >= kReset;
    const PoseSample s =
        sample((after ? T_world_F1 : T_world_F0).inverse() * truth, after ? 1 : 0, i);
    PoseSample o;
    ASSERT_TRUE(a.align(s, o));
    out.push_back(o.T_tracker_head);
    if (i > 0) {
      const Pose prev = truth_at((i - 1) * kDt);
      max_truth_step_m = std::max(max_truth_step_m, (truth.t - prev.t).norm());
      max_truth_step_rad = std::max(max_truth_step_rad, rot_angle(truth.R, prev.R));
      // What the screen would show without re-solving: the configured frame applied blindly.
      const Pose raw = T_world_F0 * s.T_tracker_head;
      const Pose raw_prev =
          T_world_F0 * ((i - 1 >= kReset ? T_world_F1 : T_world_F0).inverse() * prev);
      max_raw_step_m = std::max(max_raw_step_m, (raw.t - raw_prev.t).norm());
    }
  }
  EXPECT_EQ(a.tracker_resets(), 1u);
  EXPECT_GT(max_raw_step_m, 0.3) << "the test's jump must be visible without alignment";
  double max_step_m = 0.0, max_step_rad = 0.0;
  for (int i = 1; i < kN; ++i) {
    max_step_m = std::max(max_step_m, (out[i].t - out[i - 1].t).norm());
    max_step_rad = std::max(max_step_rad, rot_angle(out[i].R, out[i - 1].R));
  }
  EXPECT_LE(max_step_m, max_truth_step_m + 1e-12);
  EXPECT_LE(max_step_rad, max_truth_step_rad + 1e-9);
  // Closed form: before the reset out = truth; at the reset sample out = the last pre-reset pose;
  // after it out = D * truth with the constant D = truth(k-1) truth(k)^-1.
  EXPECT_LT((out[kReset].t - out[kReset - 1].t).norm(), 1e-12);
  EXPECT_LT(rot_angle(out[kReset].R, out[kReset - 1].R), 1e-9);
  const Pose D = truth_at((kReset - 1) * kDt) * truth_at(kReset * kDt).inverse();
  for (int i = 0; i < kN; ++i) {
    const Pose expect = i < kReset ? truth_at(i * kDt) : D * truth_at(i * kDt);
    EXPECT_LT((out[i].t - expect.t).norm(), 1e-9) << "sample " << i;
    EXPECT_LT(rot_angle(out[i].R, expect.R), 1e-9) << "sample " << i;
  }
}

TEST(TrackingAlignment, OrientationOnlyTrackerResetKeepsPosition) {
  const Pose T_world_tracker{Eigen::Matrix3d::Identity(), {0.0, -0.3, 0.0}};
  TrackerAlignment a(config(T_world_tracker));
  PoseSample o1, o2;
  PoseSample s1 = sample({ypr(0.2, 0.1, 0.0), Eigen::Vector3d::Zero()}, 5);
  s1.has_position = false;
  ASSERT_TRUE(a.align(s1, o1));
  // The tracker re-zeroes its yaw: the same physical head now reads as heading 0.
  PoseSample s2 = sample({ypr(0.0, 0.1, 0.0), Eigen::Vector3d::Zero()}, 6);
  s2.has_position = false;
  ASSERT_TRUE(a.align(s2, o2));
  EXPECT_LT(rot_angle(o2.T_tracker_head.R, o1.T_tracker_head.R), 1e-12);
  EXPECT_LT((o2.T_tracker_head.t - Eigen::Vector3d(0.0, -0.3, 0.0)).norm(), 1e-12);
  EXPECT_EQ(a.tracker_resets(), 1u);
  EXPECT_EQ(o2.reset_counter, 0u);  // seamless: downstream sees no jump
}

TEST(TrackingAlignment, BadPosesAreRejectedAndChangeNothing) {
  TrackerAlignment a(config({rot(0.2, kUp), {0.0, 0.0, 1.0}}));
  PoseSample good_out, bad_out;
  ASSERT_TRUE(a.align(sample({Eigen::Matrix3d::Identity(), {0.1, 0.0, 0.0}}), good_out));
  PoseSample nan = sample({Eigen::Matrix3d::Identity(), {std::nan(""), 0.0, 0.0}}, 3);
  bad_out.sequence = 999;
  EXPECT_FALSE(a.align(nan, bad_out));
  EXPECT_EQ(bad_out.sequence, 999u) << "out untouched";
  PoseSample scaled = sample({2.0 * Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero()});
  EXPECT_FALSE(a.align(scaled, bad_out));
  EXPECT_FALSE(a.recentre(nan));
  EXPECT_EQ(a.rejected(), 2u);
  EXPECT_EQ(a.tracker_resets(), 0u) << "a rejected sample's counter is not adopted";
  EXPECT_EQ(a.recentres(), 0u);
  PoseSample again;
  ASSERT_TRUE(a.align(sample({Eigen::Matrix3d::Identity(), {0.1, 0.0, 0.0}}), again));
  EXPECT_LT((again.T_tracker_head.t - good_out.T_tracker_head.t).norm(), 1e-15);
}

TEST(TrackingAlignment, BadConfigurationIsRefusedByName) {
  TrackerAlignmentConfig c = config(Pose::identity());
  c.T_world_tracker.R(0, 0) = 3.0;
  try {
    TrackerAlignment a(c);
    FAIL() << "accepted a non-rotation";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("T_world_tracker"), std::string::npos) << e.what();
  }
  c = config(Pose::identity());
  c.up_world = Eigen::Vector3d::Zero();
  EXPECT_THROW(TrackerAlignment{c}, std::invalid_argument);
  c = config(Pose::identity());
  c.T_world_home.t.x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(TrackerAlignment{c}, std::invalid_argument);
}

TEST(TrackingAlignment, RestoreConfiguredUndoesRecentre) {
  const Pose T{rot(0.5, kUp), {0.2, 0.0, 0.1}};
  TrackerAlignment a(config(T, Pose{ypr(1.0, 0.0, 0.0), {0.0, 0.0, 0.5}}));
  const PoseSample s = sample({ypr(0.1, 0.2, 0.0), {0.3, 0.1, 0.0}});
  ASSERT_TRUE(a.recentre(s));
  a.restore_configured();
  PoseSample o;
  ASSERT_TRUE(a.align(s, o));
  const Pose expect = T * s.T_tracker_head;
  EXPECT_LT((o.T_tracker_head.t - expect.t).norm(), 1e-15);
  EXPECT_EQ(o.reset_counter, 2u);  // recentre + restore: two world jumps
}

// --- properties ---------------------------------------------------------------------------

double uniform(double lo, double hi) {
  return lo + (hi - lo) * (*rc::gen::inRange(0, 1'000'001)) * 1e-6;
}

Pose random_pose(double max_t_m) {
  const Eigen::Vector3d axis(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
  const double angle = uniform(-kPi, kPi);
  const Eigen::Matrix3d R = axis.norm() < 1e-3 ? Eigen::Matrix3d::Identity() : rot(angle, axis);
  return {R, {uniform(-max_t_m, max_t_m), uniform(-max_t_m, max_t_m), uniform(-max_t_m, max_t_m)}};
}

RC_GTEST_PROP(TrackingAlignmentProperty, RandomResetsNeverJumpMoreThanOneSampleOfMotion, ()) {
  const Pose T_world_tracker = random_pose(2.0);
  TrackerAlignment a(config(T_world_tracker));
  const double phase = uniform(0, 10), dt = uniform(0.002, 0.02);
  const int n = *rc::gen::inRange(20, 200);
  const auto reset_at =
      *rc::gen::container<std::vector<int>>(*rc::gen::inRange(0, 5), rc::gen::inRange(1, n));
  Pose frame = T_world_tracker;  // the tracker's true frame in the world
  uint32_t counter = *rc::gen::arbitrary<uint32_t>();
  std::vector<Pose> out, truth;
  uint64_t resets = 0;
  for (int i = 0; i < n; ++i) {
    bool jump = false;
    for (int r : reset_at) jump = jump || r == i;
    if (jump) {
      frame = frame * random_pose(1.0);
      ++counter;  // wraps like the HID 8-bit counter does, still a change
      ++resets;
    }
    truth.push_back(truth_at(phase + i * dt));
    PoseSample o;
    RC_ASSERT(a.align(sample(frame.inverse() * truth.back(), counter, i), o));
    out.push_back(o.T_tracker_head);
    RC_ASSERT(o.reset_counter == 0u);
  }
  RC_ASSERT(a.tracker_resets() == resets);
  for (int i = 1; i < n; ++i) {
    const double step_m = (out[i].t - out[i - 1].t).norm();
    const double truth_m = (truth[i].t - truth[i - 1].t).norm();
    const double step_rad = rot_angle(out[i].R, out[i - 1].R);
    const double truth_rad = rot_angle(truth[i].R, truth[i - 1].R);
    bool reset_here = false;
    for (int r : reset_at) reset_here = reset_here || r == i;
    if (reset_here) {  // the first sample after a reset repeats the last world pose
      RC_ASSERT(step_m < 1e-9);
      RC_ASSERT(step_rad < 1e-7);
    } else {  // otherwise the world moves exactly as the head does
      RC_ASSERT(std::abs(step_m - truth_m) < 1e-9);
      RC_ASSERT(std::abs(step_rad - truth_rad) < 1e-7);
    }
  }
}

RC_GTEST_PROP(TrackingAlignmentProperty, RecentreReachesHomeAndKeepsTilt, ()) {
  const Pose T_world_tracker = random_pose(2.0);
  const Pose home = random_pose(1.0);
  TrackerAlignment a(config(T_world_tracker, home));
  const PoseSample s = sample(random_pose(1.0));
  const Pose before = a.to_world(s.T_tracker_head);
  RC_ASSERT(a.recentre(s));
  PoseSample o;
  RC_ASSERT(a.align(s, o));
  const Pose& after = o.T_tracker_head;
  RC_ASSERT((after.t - home.t).norm() < 1e-9);
  for (int axis = 0; axis < 3; ++axis)
    RC_ASSERT(std::abs(after.R.col(axis).dot(kUp) - before.R.col(axis).dot(kUp)) < 1e-9);
  // Same heading as home, checked through the forward axis where it is not near vertical.
  Eigen::Vector3d f_after = after.R.col(2) - after.R.col(2).dot(kUp) * kUp;
  Eigen::Vector3d f_home = home.R.col(2) - home.R.col(2).dot(kUp) * kUp;
  if (f_after.norm() > 1e-2 && f_home.norm() > 1e-2)
    RC_ASSERT((f_after.normalized() - f_home.normalized()).norm() < 1e-7);
  RC_ASSERT(after.R.allFinite());
}

}  // namespace
