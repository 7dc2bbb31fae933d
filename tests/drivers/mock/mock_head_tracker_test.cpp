// The real HidHeadTracker and parser on the simulated Android head tracker: byte-exact reports
// from a scripted motion, end to end.
#include "drivers/mock/mock_head_tracker_transport.h"

#include <gtest/gtest.h>

#include <vector>

#include "drivers/hid/hid_head_tracker.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

MockHeadTrackerConfig yawing_tracker() {
  MockHeadTrackerConfig c;
  c.motion = [](double t) {
    TrajectorySample s;
    s.q = Eigen::AngleAxisd(1.0 * t, Eigen::Vector3d::UnitY());  // 1 rad/s about station y
    return s;
  };
  return c;
}

TEST(MockHeadTracker, RealTrackerDecodesScriptedMotionEndToEnd) {
  MockHeadTrackerConfig dev = yawing_tracker();
  HidHeadTracker t(
      {.id = "sim", .opener = mock_head_tracker_opener(dev), .report_interval_ms = 10});
  t.start();
  ASSERT_TRUE(eventually([&] { return t.latest().published() >= 12; }));
  t.stop();
  EXPECT_EQ(t.rejected_reports(), 0u);
  std::vector<PoseSample> all;
  PoseSample s;
  while (t.history().pop(s)) all.push_back(s);
  ASSERT_GE(all.size(), 12u);
  for (std::size_t i = 0; i < all.size(); ++i) {
    // A pure rotation about y: the rotation vector's x and z stay within quantisation
    // (pi / 32767 per component, after the head-axes change).
    const Eigen::AngleAxisd aa(all[i].T_tracker_head.R);
    const Eigen::Vector3d rv = aa.axis() * aa.angle();
    EXPECT_NEAR(rv.x(), 0.0, 2e-4) << rv.transpose();
    EXPECT_NEAR(rv.z(), 0.0, 2e-4) << rv.transpose();
    // 1 rad/s about y, quantised to 32/32767 rad/s.
    EXPECT_NEAR(all[i].angular_velocity_rad_s.y(), 1.0, 2e-3);
    EXPECT_NEAR(all[i].angular_velocity_rad_s.x(), 0.0, 2e-3);
    if (i > 0) {
      // Reports are 10 ms apart on the device: 0.01 rad of yaw each.
      const Eigen::AngleAxisd step(all[i - 1].T_tracker_head.R.transpose() *
                                   all[i].T_tracker_head.R);
      EXPECT_NEAR(step.angle(), 0.010, 3e-4);
    }
  }
}

TEST(MockHeadTracker, DiscontinuityAndReplugReachTheTracker) {
  MockHeadTrackerConfig dev = yawing_tracker();
  auto control = dev.control;
  HidHeadTracker t({.id = "sim",
                    .opener = mock_head_tracker_opener(dev),
                    .reopen_interval_ns = 10'000'000,
                    .read_timeout_ms = 5});
  t.start();
  ASSERT_TRUE(eventually([&] { return t.latest().published() >= 3; }));
  control->discontinuity = 1;
  ASSERT_TRUE(
      eventually([&] { return t.latest().fetch() && t.latest().latest().reset_counter == 1; }));
  control->plugged_in = false;
  ASSERT_TRUE(eventually([&] { return t.state() == SourceState::kDisconnected; }));
  control->plugged_in = true;
  ASSERT_TRUE(
      eventually([&] { return t.reconnects() == 1 && t.state() == SourceState::kStreaming; }));
  const uint64_t before = t.latest().published();
  ASSERT_TRUE(eventually([&] { return t.latest().published() > before + 2; }));
  ASSERT_TRUE(t.latest().fetch());
  EXPECT_EQ(t.latest().latest().reset_counter, 2u);  // one jump + one reconnect
  t.stop();
}

}  // namespace
}  // namespace hd::drivers
