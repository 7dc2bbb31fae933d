// CameraNeedPolicy: the chosen camera and the runner-up are always needed, any camera under
// m_t + margin too; a camera leaves only after hold_s unwanted, and comes back at once.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "station/selection/camera_need.h"

namespace hd::station {
namespace {

constexpr int64_t kMs = 1'000'000;
const double kInf = std::numeric_limits<double>::infinity();

TEST(CameraNeed, EveryCameraIsNeededUntilTheFirstHoldHasPassed) {
  CameraNeedPolicy p(3, {40.0, 20.0, 2.0});
  for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(p.needed(i));  // no update yet: full rate
  const std::vector<double> m = {10.0, 30.0, 500.0};
  p.update(m, 0, 0);
  EXPECT_TRUE(p.needed(2));  // wanted "just now" at the first frame: the hold starts there
  p.update(m, 0, 1999 * kMs);
  EXPECT_TRUE(p.needed(2));
  p.update(m, 0, 2000 * kMs);
  EXPECT_FALSE(p.needed(2));  // 2 s unwanted (m = 500 > 60, not chosen, not runner-up)
  EXPECT_TRUE(p.needed(0));   // chosen
  EXPECT_TRUE(p.needed(1));   // runner-up (and under 60)
  EXPECT_EQ(p.changes(), 1u);
}

TEST(CameraNeed, TheRunnerUpIsNeededWhateverItsM) {
  CameraNeedPolicy p(3, {40.0, 20.0, 0.5});
  const std::vector<double> m = {10.0, 300.0, 500.0};
  p.update(m, 0, 0);
  p.update(m, 0, 600 * kMs);
  EXPECT_TRUE(p.needed(1));  // the best of the others, though far above m_t + margin
  EXPECT_FALSE(p.needed(2));
}

TEST(CameraNeed, ACameraNearTheThresholdDoesNotFlapAndComesBackAtOnce) {
  CameraNeedPolicy p(3, {40.0, 20.0, 1.0});
  // Camera 2's m wanders across m_t + margin = 60 every 100 ms: never unwanted for 1 s.
  int64_t t = 0;
  for (int k = 0; k < 50; ++k, t += 100 * kMs) {
    const std::vector<double> m = {10.0, 20.0, k % 2 ? 61.0 : 59.0};
    p.update(m, 0, t);
    EXPECT_TRUE(p.needed(2)) << k;
  }
  EXPECT_EQ(p.changes(), 0u);
  // Then it stays above: not needed 1 s after it was last under.
  const int64_t last_under = t - 200 * kMs;  // k = 48 was the last even k
  for (; t < last_under + 1000 * kMs; t += 100 * kMs) {
    p.update(std::vector<double>{10.0, 20.0, 61.0}, 0, t);
    EXPECT_TRUE(p.needed(2));
  }
  p.update(std::vector<double>{10.0, 20.0, 61.0}, 0, t);
  EXPECT_FALSE(p.needed(2));
  // Under the threshold again: needed in that same frame.
  p.update(std::vector<double>{10.0, 20.0, 59.9}, 0, t + kMs);
  EXPECT_TRUE(p.needed(2));
  EXPECT_EQ(p.changes(), 2u);
  // Both changes were camera 2's: the per-camera counts add up to the total.
  EXPECT_EQ(p.changes(2), 2u);
  EXPECT_EQ(p.changes(0), 0u);
  EXPECT_EQ(p.changes(1), 0u);
}

TEST(CameraNeed, AnUnusableCameraIsNotWantedByTheThresholdButTheChosenOneAlways) {
  CameraNeedPolicy p(2, {40.0, 20.0, 0.0});
  p.update(std::vector<double>{kInf, std::numeric_limits<double>::quiet_NaN()}, 1, 0);
  EXPECT_TRUE(p.needed(1));   // chosen, even with NaN m
  EXPECT_FALSE(p.needed(0));  // +inf: no runner-up, no threshold, no hold (0 s)
}

TEST(CameraNeed, AKeptCameraIsAlwaysNeeded) {
  CameraNeedPolicy p(3, {40.0, 20.0, 0.0});
  p.keep(2);
  p.update(std::vector<double>{10.0, 20.0, 900.0}, 0, 0);
  p.update(std::vector<double>{10.0, 20.0, 900.0}, 0, 5000 * kMs);
  EXPECT_TRUE(p.needed(2));
}

}  // namespace
}  // namespace hd::station
