// AlignedPoseSource: republishes a wrapped source's samples in the workspace frame, applies a
// re-centre requested from another thread to the next sample, forwards id/state/rejected, makes a
// tracker reset seamless, and allocates nothing per sample.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <thread>

#include "core/allocation_counter.h"
#include "drivers/mock/mock_pose_source.h"
#include "station/tracking/aligned_pose_source.h"
#include "test_wait.h"

namespace {

using hd::core::Pose;
using hd::drivers::PoseSample;
using hd::drivers::SourceState;
using hd::station::AlignedPoseSource;
using hd::station::AlignedPoseSourceConfig;

const Eigen::Vector3d kUp{0.0, -1.0, 0.0};

Eigen::Matrix3d rot(double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// A pose device the test feeds by hand.
class HandFedPoseSource final : public hd::drivers::PoseSource {
 public:
  std::string id() const override { return "hand-fed"; }
  void open() override { ++opens; }
  void start() override { ++starts; }
  void stop() override { ++stops; }
  SourceState state() const override { return SourceState::kStalled; }
  uint64_t rejected_reports() const override { return 7; }
  hd::drivers::Mailbox<PoseSample>& latest() override { return latest_; }
  hd::drivers::SpscRing<PoseSample, 1024>& history() override { return ring; }

  void feed(const Pose& T_tracker_head, uint32_t reset_counter = 0) {
    PoseSample s;
    s.T_tracker_head = T_tracker_head;
    s.has_position = true;
    s.reset_counter = reset_counter;
    s.sequence = next_seq++;
    s.host_timestamp_ns = static_cast<int64_t>(s.sequence) * 2'000'000;
    ASSERT_TRUE(ring.push(s));
  }

  hd::drivers::SpscRing<PoseSample, 1024> ring;
  int opens = 0, starts = 0, stops = 0;
  uint64_t next_seq = 0;

 private:
  hd::drivers::Mailbox<PoseSample> latest_;
};

AlignedPoseSourceConfig config(const Pose& T_world_tracker, const Pose& home) {
  AlignedPoseSourceConfig c;
  c.alignment.T_world_tracker = T_world_tracker;
  c.alignment.T_world_home = home;
  c.alignment.up_world = kUp;
  return c;
}

std::vector<PoseSample> drain(AlignedPoseSource& s) {
  std::vector<PoseSample> out;
  PoseSample x;
  while (s.history().pop(x)) out.push_back(x);
  return out;
}

TEST(TrackingAlignedPoseSource, RepublishesInWorldFrameAndForwards) {
  HandFedPoseSource inner;
  const Pose T_world_tracker{rot(0.5, kUp), {0.0, -0.2, 0.3}};
  AlignedPoseSource src(inner, config(T_world_tracker, Pose::identity()));
  EXPECT_EQ(src.id(), "hand-fed");
  EXPECT_EQ(src.state(), SourceState::kStalled);
  src.open();
  EXPECT_EQ(inner.opens, 1);
  const Pose head{rot(0.2, {1, 0, 0}), {0.1, 0.0, 0.4}};
  inner.feed(head);
  inner.feed(head);
  EXPECT_EQ(src.pump(), 2);
  const auto out = drain(src);
  ASSERT_EQ(out.size(), 2u);
  const Pose expect = T_world_tracker * head;
  EXPECT_LT((out[1].T_tracker_head.t - expect.t).norm(), 1e-12);
  EXPECT_LT((out[1].T_tracker_head.R - expect.R).norm(), 1e-12);
  EXPECT_EQ(out[1].sequence, 1u);
  ASSERT_TRUE(src.latest().fetch());
  EXPECT_EQ(src.latest().latest().sequence, 1u);
  // A non-finite pose is dropped and counted on top of the wrapped source's own count.
  inner.feed({Eigen::Matrix3d::Identity(), {std::nan(""), 0, 0}});
  EXPECT_EQ(src.pump(), 0);
  EXPECT_EQ(src.rejected_reports(), 7u + 1u);
  EXPECT_EQ(src.samples(), 2u);
}

TEST(TrackingAlignedPoseSource, RecentreFromAnotherThreadAppliesToTheNextSampleOnly) {
  HandFedPoseSource inner;
  const Pose home{rot(-0.3, kUp), {0.0, -0.1, 0.5}};
  AlignedPoseSource src(inner, config(Pose{rot(1.0, kUp), {1.0, 0.0, 0.0}}, home));
  const Pose head{rot(0.7, kUp) * rot(0.25, Eigen::Vector3d::UnitX()), {0.3, 0.05, -0.2}};
  inner.feed(head);
  src.pump();
  std::thread key([&] {
    src.request_recentre();
    src.request_recentre();
  });  // the window key
  key.join();
  inner.feed(head);
  const Pose moved{head.R, head.t + Eigen::Vector3d(0.0, 0.0, 0.1)};
  inner.feed(moved);
  EXPECT_EQ(src.pump(), 2);
  EXPECT_EQ(src.recentres(), 1u) << "two requests before one sample count once";
  const auto out = drain(src);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].reset_counter, 0u);
  // The re-centred sample sits at home; its heading is home's, its pitch (0.25 rad) is kept.
  EXPECT_LT((out[1].T_tracker_head.t - home.t).norm(), 1e-12);
  const Eigen::Matrix3d expect_R = rot(-0.3, kUp) * rot(0.25, Eigen::Vector3d::UnitX());
  EXPECT_LT((out[1].T_tracker_head.R - expect_R).norm(), 1e-12);
  EXPECT_EQ(out[1].reset_counter, 1u) << "the world jumped on purpose: predictors restart";
  // The next sample moved 0.1 m in the tracker: 0.1 m in the world, no second re-centre.
  EXPECT_NEAR((out[2].T_tracker_head.t - out[1].T_tracker_head.t).norm(), 0.1, 1e-12);
  EXPECT_EQ(out[2].reset_counter, 1u);
}

TEST(TrackingAlignedPoseSource, TrackerResetIsSeamless) {
  HandFedPoseSource inner;
  AlignedPoseSource src(inner, config(Pose::identity(), Pose::identity()));
  const Pose head{rot(0.4, kUp), {0.2, 0.0, 0.0}};
  inner.feed(head, 3);
  // The tracker's frame turns 90 deg and shifts; the same physical head reads differently.
  const Pose jump{rot(1.57, {0.2, 1, 0}), {0.5, 0.1, -0.4}};
  inner.feed(jump.inverse() * head, 4);
  src.pump();
  const auto out = drain(src);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_LT((out[1].T_tracker_head.t - out[0].T_tracker_head.t).norm(), 1e-12);
  EXPECT_LT((out[1].T_tracker_head.R - out[0].T_tracker_head.R).norm(), 1e-12);
  EXPECT_EQ(out[1].reset_counter, 0u);
  EXPECT_EQ(src.tracker_resets(), 1u);
}

TEST(TrackingAlignedPoseSource, PumpAllocatesNothingPerSample) {
  HandFedPoseSource inner;
  AlignedPoseSource src(inner, config(Pose{rot(0.1, kUp), {0, 0, 1}}, Pose::identity()));
  for (int i = 0; i < 500; ++i) inner.feed({rot(0.001 * i, kUp), {0.001 * i, 0, 0}}, i / 100);
  src.request_recentre();
  hd::core::reset_counted_allocations();
  hd::core::count_allocations_on_this_thread(true);
  const int n = src.pump();
  hd::core::count_allocations_on_this_thread(false);
  EXPECT_EQ(n, 500);
  EXPECT_EQ(hd::core::counted_allocations(), 0u);
  EXPECT_EQ(src.tracker_resets(), 4u);
}

TEST(TrackingAlignedPoseSource, BadConfigurationIsRefused) {
  HandFedPoseSource inner;
  AlignedPoseSourceConfig c = config(Pose::identity(), Pose::identity());
  c.idle_sleep_ns = 0;
  EXPECT_THROW(AlignedPoseSource(inner, c), std::invalid_argument);
  c = config(Pose{2.0 * Eigen::Matrix3d::Identity(), {0, 0, 0}}, Pose::identity());
  EXPECT_THROW(AlignedPoseSource(inner, c), std::invalid_argument);
}

TEST(TrackingAlignedPoseSource, ThreadedOverMockTrackerRecentresOnRequest) {
  // A still head at tracker (0.4, 0, 0.2), turned 0.6 rad about the tracker's y, tilted 0.2 rad.
  const Eigen::Quaterniond q(rot(0.6, Eigen::Vector3d::UnitY()) *
                             rot(0.2, Eigen::Vector3d::UnitX()));
  hd::drivers::MockPoseSourceConfig mc;
  mc.motion = [q](double) {
    hd::drivers::TrajectorySample s;
    s.q = q;
    s.position_m = {0.4, 0.0, 0.2};
    return s;
  };
  mc.rate_hz = 1000.0;
  hd::drivers::MockPoseSource mock(mc);
  const Pose home{Eigen::Matrix3d::Identity(), {0.0, -0.3, 0.6}};
  AlignedPoseSource src(mock, config(Pose::identity(), home));
  src.start();
  ASSERT_TRUE(eventually([&] { return src.samples() >= 5; }));
  std::thread key([&] { src.request_recentre(); });
  key.join();
  ASSERT_TRUE(eventually([&] { return src.recentres() == 1; }));
  const uint64_t after = src.samples();
  ASSERT_TRUE(eventually([&] { return src.samples() >= after + 3; }));
  src.stop();
  ASSERT_TRUE(src.latest().fetch());
  const PoseSample& s = src.latest().latest();
  EXPECT_EQ(s.reset_counter, 1u);
  EXPECT_LT((s.T_tracker_head.t - home.t).norm(), 1e-9);
  // Heading removed (home faces +z), the 0.2 rad tilt about x kept.
  EXPECT_LT((s.T_tracker_head.R - rot(0.2, Eigen::Vector3d::UnitX())).norm(), 1e-9);
  EXPECT_EQ(src.state(), SourceState::kClosed);
}

}  // namespace
