#include "drivers/mock/mock_pose_source.h"

#include <gtest/gtest.h>

#include <vector>

#include "drivers/camera_source.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

ScriptedMotion yaw_at(double rate_rad_s) {
  return [rate_rad_s](double t) {
    TrajectorySample s;
    s.q = Eigen::AngleAxisd(rate_rad_s * t, Eigen::Vector3d::UnitY());
    s.position_m = {0.1 * t, 0, 0};
    return s;
  };
}

TEST(MockPoseSource, AngularVelocityOfConstantRotationIsItsRate) {
  MockPoseSource src({.motion = yaw_at(0.7)});
  const PoseSample s = src.sample_at(2.0);
  EXPECT_TRUE(s.angular_velocity_rad_s.isApprox(Eigen::Vector3d(0, 0.7, 0), 1e-6))
      << s.angular_velocity_rad_s.transpose();
  EXPECT_TRUE(s.T_tracker_head.R.isApprox(
      Eigen::AngleAxisd(1.4, Eigen::Vector3d::UnitY()).toRotationMatrix(), 1e-12));
  EXPECT_NEAR(s.T_tracker_head.t.x(), 0.2, 1e-12);
}

TEST(MockPoseSource, PublishesEverySampleInOrderAtItsRate) {
  MockPoseSource src({.motion = yaw_at(1.0), .rate_hz = 1000.0});
  src.start();
  ASSERT_TRUE(eventually([&] { return src.latest().published() >= 30; }));
  src.stop();
  std::vector<PoseSample> all;
  PoseSample s;
  while (src.history().pop(s)) all.push_back(s);
  ASSERT_GE(all.size(), 30u);
  for (std::size_t i = 1; i < all.size(); ++i) {
    EXPECT_EQ(all[i].sequence, all[i - 1].sequence + 1);
    EXPECT_EQ(all[i].host_timestamp_ns - all[i - 1].host_timestamp_ns, 1'000'000);
  }
  // Each sample's pose is the motion at its own timestamp.
  const double t = static_cast<double>(all[20].device_timestamp_ns) * 1e-9;
  EXPECT_NEAR(Eigen::AngleAxisd(all[20].T_tracker_head.R).angle(), t, 1e-9);
  EXPECT_EQ(src.state(), SourceState::kClosed);
}

TEST(MockPoseSource, OpenWithoutMotionOrWithBadRateThrows) {
  MockPoseSource none({.id = "walk"});
  EXPECT_THROW(none.open(), DeviceError);
  MockPoseSource bad({.motion = yaw_at(1), .rate_hz = -5});
  EXPECT_THROW(bad.open(), DeviceError);
}

}  // namespace
}  // namespace hd::drivers
