// PoseHistory: validation, resets, the fixed window and draining a device ring.
#include <gtest/gtest.h>

#include <limits>

#include "station/prediction/pose_history.h"

namespace hd::station {
namespace {

drivers::PoseSample at(int64_t t_ns, double x = 0.0) {
  drivers::PoseSample s;
  s.T_tracker_head.t = Eigen::Vector3d(x, 0, 0);
  s.has_position = true;
  s.host_timestamp_ns = t_ns;
  return s;
}

class CountingPredictor final : public PosePredictor {
 public:
  std::string_view name() const override { return "count"; }
  void reset() override { ++resets; }
  void observe(const HeadSample&) override { ++observed; }
  bool ready() const override { return observed > 0; }
  core::Pose predict(int64_t) const override { return {}; }
  int resets = 0;
  int observed = 0;
};

TEST(PredictionPoseHistory, RejectsMalformedSamplesAndCountsThem) {
  PoseHistory h;
  CountingPredictor p;
  EXPECT_TRUE(h.add(at(10), &p));
  auto nan = at(20);
  nan.T_tracker_head.t.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(h.add(nan, &p));
  EXPECT_NE(h.last_rejection().find("rotation"), std::string_view::npos);
  auto skewed = at(30);
  skewed.T_tracker_head.R(0, 1) = 0.5;
  EXPECT_FALSE(h.add(skewed, &p));
  EXPECT_FALSE(h.add(at(10), &p));  // not after the previous sample
  EXPECT_NE(h.last_rejection().find("host_timestamp_ns"), std::string_view::npos);
  auto bad_gyro = at(40);
  bad_gyro.has_angular_velocity = true;
  bad_gyro.angular_velocity_rad_s.y() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(h.add(bad_gyro, &p));
  EXPECT_EQ(h.rejected(), 4u);
  EXPECT_EQ(h.accepted(), 1u);
  EXPECT_EQ(p.observed, 1);
}

TEST(PredictionPoseHistory, ResetCounterClearsHistoryAndPredictor) {
  PoseHistory h;
  CountingPredictor p;
  for (int i = 1; i <= 5; ++i) ASSERT_TRUE(h.add(at(i * 10), &p));
  auto jumped = at(60);
  jumped.reset_counter = 1;
  ASSERT_TRUE(h.add(jumped, &p));
  EXPECT_EQ(h.size(), 1u);
  EXPECT_EQ(h.resets(), 1u);
  EXPECT_EQ(p.resets, 1);
}

TEST(PredictionPoseHistory, KeepsTheNewestWindowInOrder) {
  PoseHistory h;
  const int n = static_cast<int>(PoseHistory::kCapacity) + 37;
  for (int i = 1; i <= n; ++i) ASSERT_TRUE(h.add(at(i, i), nullptr));
  ASSERT_EQ(h.size(), PoseHistory::kCapacity);
  EXPECT_EQ(h.newest().t_ns, n);
  EXPECT_EQ(h.at(0).t_ns, n - static_cast<int>(PoseHistory::kCapacity) + 1);
  for (std::size_t i = 1; i < h.size(); ++i) EXPECT_EQ(h.at(i).t_ns, h.at(i - 1).t_ns + 1);
}

TEST(PredictionPoseHistory, PullDrainsTheDeviceRing) {
  static PoseHistory::Ring ring;  // large: keep it off the stack
  PoseHistory h;
  CountingPredictor p;
  for (int i = 1; i <= 100; ++i) ASSERT_TRUE(ring.push(at(i * 1000)));
  EXPECT_EQ(h.pull(ring, &p), 100);
  EXPECT_EQ(h.pull(ring, &p), 0);
  EXPECT_EQ(p.observed, 100);
  EXPECT_EQ(h.newest().t_ns, 100'000);
}

}  // namespace
}  // namespace hd::station
