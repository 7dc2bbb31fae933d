// RateGovernor against hand-made work times: when it slows down (three overruns of the last
// eight frames), to which divisor (the third-longest work's), and when it speeds up again (every
// frame fitting the faster rate for the recovery time, and as long since the last change).
#include "render/loop/rate_governor.h"

#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>

namespace hd::render {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kPeriod = 11'111'111;  // 90 Hz

RateGovernorConfig at_90_hz() {
  RateGovernorConfig c;
  c.display_hz = 90.0;
  c.headroom = 0.85;  // 9.44 ms at 90 Hz, 18.9 at 45, 28.3 at 30, 37.8 at 22.5
  c.recover_ns = 3'000 * kMs;
  return c;
}

TEST(RateGovernor, WorkThatFitsKeepsTheDisplayRateAndTwoOverrunsAreForgiven) {
  RateGovernor g(at_90_hz());
  int64_t t = 0;
  for (int i = 0; i < 100; ++i, t += kPeriod) {
    const int64_t work = i % 8 < 2 ? 15 * kMs : 5 * kMs;  // two slow frames in every eight
    EXPECT_EQ(g.observe(work, t), std::nullopt) << "frame " << i;
  }
  EXPECT_EQ(g.divisor(), 1);
  EXPECT_DOUBLE_EQ(g.rate_hz(), 90.0);
}

TEST(RateGovernor, ThreeOverrunsSlowItToTheRateTheThirdLongestWorkFits) {
  RateGovernor g(at_90_hz());
  int64_t t = 0;
  EXPECT_EQ(g.observe(5 * kMs, t += kPeriod), std::nullopt);
  EXPECT_EQ(g.observe(40 * kMs, t += kPeriod), std::nullopt);  // longest: fits no rate
  EXPECT_EQ(g.observe(26 * kMs, t += kPeriod), std::nullopt);
  // The third overrun: the third-longest is 20 ms, over 45 Hz's 18.9, within 30 Hz's 28.3.
  EXPECT_EQ(g.observe(20 * kMs, t += kPeriod), std::optional<int>(3));
  EXPECT_NEAR(g.rate_hz(), 30.0, 1e-12);
  // At 30 Hz, work of 20 ms fits: it stays.
  for (int i = 0; i < 20; ++i) EXPECT_EQ(g.observe(20 * kMs, t += 3 * kPeriod), std::nullopt);
  EXPECT_EQ(g.divisor(), 3);
}

TEST(RateGovernor, ItNeverGoesBelowTheSlowestRate) {
  RateGovernorConfig c = at_90_hz();
  c.max_divisor = 2;
  RateGovernor g(c);
  int64_t t = 0;
  std::optional<int> changed;
  for (int i = 0; i < 3; ++i) changed = g.observe(100 * kMs, t += kPeriod);
  EXPECT_EQ(changed, std::optional<int>(2));
  for (int i = 0; i < 20; ++i) EXPECT_EQ(g.observe(100 * kMs, t += 2 * kPeriod), std::nullopt);
  EXPECT_EQ(g.divisor(), 2);
}

TEST(RateGovernor, ItSpeedsUpOneStepOnceEveryFrameFitTheFasterRateForTheRecoveryTime) {
  RateGovernor g(at_90_hz());
  int64_t t = 0;
  for (int i = 0; i < 3; ++i) g.observe(30 * kMs, t += kPeriod);
  ASSERT_EQ(g.divisor(), 4);  // 30 ms fits only 22.5 Hz's 37.8
  // Work of 17 ms fits 30 Hz's 28.3 (and 45 Hz's 18.9). One frame of 29 ms at 2.0 s restarts the
  // 3 s of fitting 30 Hz.
  const int64_t changed_at = t;
  std::optional<int> step;
  for (; !step; t += 4 * kPeriod) {
    step = g.observe(t - changed_at >= 2'000 * kMs && t - changed_at < 2'000 * kMs + 4 * kPeriod
                         ? 29 * kMs
                         : 17 * kMs,
                     t);
  }
  EXPECT_EQ(step, std::optional<int>(3));
  const int64_t took = t - 4 * kPeriod - changed_at;
  EXPECT_GE(took, 5'000 * kMs);  // the slow frame at 2 s, then 3 s more
  EXPECT_LT(took, 5'000 * kMs + 8 * kPeriod);
  // And on to 45 Hz after another 3 s (17 ms fits 18.9), never to 90 (9.4).
  int steps = 0;
  for (int i = 0; i < 2000; ++i, t += 2 * kPeriod)
    if (g.observe(17 * kMs, t)) ++steps;
  EXPECT_EQ(steps, 1);
  EXPECT_EQ(g.divisor(), 2);
}

TEST(RateGovernor, RefusesASettingOutsideItsRange) {
  RateGovernorConfig c = at_90_hz();
  c.display_hz = 0.0;
  EXPECT_THROW(RateGovernor{c}, std::invalid_argument);
  c = at_90_hz();
  c.max_divisor = 0;
  EXPECT_THROW(RateGovernor{c}, std::invalid_argument);
  c = at_90_hz();
  c.headroom = 1.5;
  EXPECT_THROW(RateGovernor{c}, std::invalid_argument);
  c = at_90_hz();
  c.recover_ns = -1;
  EXPECT_THROW(RateGovernor{c}, std::invalid_argument);
}

}  // namespace
}  // namespace hd::render
