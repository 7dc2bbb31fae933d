// JitterBudget: the jitter buffer's latency from the link as measured (closed forms).
#include "drivers/rtp/jitter_budget.h"

#include <gtest/gtest.h>

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr uint32_t kFrameTicks = 3000;  // 30 Hz at 90 kHz

JitterBudget::Settings settings(bool retransmission) {
  JitterBudget::Settings s;
  s.min_ms = 20;
  s.max_ms = 200;
  s.start_ms = 100;
  s.retransmission = retransmission;
  s.request_wait_ms = 3;
  s.round_trip_ms = 2;
  s.margin_ms = 5;
  return s;
}

// 2 s of 30 Hz frames of 10 packets, 0.1 ms apart; frame k's packets late by late_ms(k).
template <class Late>
void stream(JitterBudget& b, Late late_ms, int frames = 60) {
  uint16_t seq = 0;
  for (int k = 0; k < frames; ++k)
    for (int p = 0; p < 10; ++p)
      b.add_packet(uint32_t(k) * kFrameTicks, seq++,
                   int64_t(k) * 100 * kMs / 3 + late_ms(k) * kMs + p * 100'000);
}

TEST(JitterBudget, StartsAtTheStartValueUntilOneSecondOfPacketsWasSeen) {
  JitterBudget b(settings(true));
  stream(
      b, [](int) { return 0; }, 20);  // 0.63 s
  EXPECT_FALSE(b.warmed_up());
  EXPECT_EQ(b.latency_ms(), 100);
}

TEST(JitterBudget, ASteadyLinkWithoutRetransmissionNeedsTheMinimum) {
  JitterBudget b(settings(false));
  stream(b, [](int) { return 0; });
  EXPECT_TRUE(b.warmed_up());
  EXPECT_NEAR(double(b.spread_ns()) / kMs, 0.9, 1e-6);  // the burst's own 0.9 ms
  EXPECT_EQ(b.latency_ms(), 20);
}

TEST(JitterBudget, TheSpreadOfLateFramesIsAddedWithAQuarterAndTheMargin) {
  JitterBudget b(settings(false));
  stream(b, [](int k) { return k % 4 == 0 ? 40 : 0; });
  EXPECT_NEAR(double(b.spread_ns()) / kMs, 40.9, 1e-6);
  // 40.9 + 40.9 / 4 + 5 = 56.125 -> 57 ms
  EXPECT_EQ(b.latency_ms(), 57);
}

TEST(JitterBudget, RetransmissionAddsTheWaitTheRoundTripAndTheRepairsOwnLateness) {
  JitterBudget b(settings(true));
  stream(b, [](int k) { return k % 4 == 0 ? 40 : 0; });
  // No repair seen: spread + wait + round trip, and the repair as late again: 40.9 + 3 + 2 +
  // 40.9 = 86.8, + 40.9 / 4 + 5 = 102.025 -> 103 ms
  EXPECT_EQ(b.latency_ms(), 103);
  // A repair seen 60 ms after its frame's earliest transit: the measured lateness, with room
  // for one more request (wait 3, round trip 2, burst pause 0.1), replaces the guess:
  // 60 + 5.1 = 65.1, + 10.225 + 5 = 80.325 -> 81 ms.
  b.add_packet(59 * kFrameTicks, 5, 59 * 100 * kMs / 3 + 60 * kMs, true);
  EXPECT_NEAR(double(b.repair_spread_ns()) / kMs, 60.0, 1e-6);
  EXPECT_NEAR(double(b.burst_gap_ns()) / kMs, 0.1, 1e-6);
  EXPECT_EQ(b.latency_ms(), 81);
  // A 30 ms round trip: 60 + 3 + 30 + 0.1 = 93.1, + 15.225 = 108.325 -> 109 ms.
  b.set_round_trip(30 * kMs);
  EXPECT_EQ(b.latency_ms(), 109);
}

TEST(JitterBudget, IsClampedToTheMaximum) {
  JitterBudget b(settings(true));
  stream(b, [](int k) { return k % 2 == 0 ? 150 : 0; });
  EXPECT_EQ(b.latency_ms(), 200);
}

TEST(JitterBudget, AnInOrderLinkHasNoReorderAndAsksAfterTheLeastWait) {
  JitterBudget b(settings(true));
  stream(b, [](int k) { return k % 3 == 0 ? 20 : 0; });
  EXPECT_EQ(b.reorder_ns(), 0);
  EXPECT_EQ(b.request_wait_ns(), 3 * kMs);
}

TEST(JitterBudget, APacketThatCameAfterALaterOneWasMissingSinceItsSuccessorCame) {
  JitterBudget b(settings(true));
  b.add_packet(0, 100, 0);
  b.add_packet(0, 102, 1 * kMs);
  b.add_packet(0, 103, 2 * kMs);
  b.add_packet(0, 101, 13 * kMs);  // its successor (102) came 12 ms before it
  EXPECT_EQ(b.reorder_ns(), 12 * kMs);
  EXPECT_EQ(b.request_wait_ns(), 12 * kMs);
}

TEST(JitterBudget, ABurstThatPausesWaitsOneAndAHalfPausesForItsEnd) {
  JitterBudget b(settings(true));
  b.add_packet(0, 1, 0);
  b.add_packet(0, 2, 1 * kMs);
  b.add_packet(0, 3, 11 * kMs);            // 10 ms pause inside the frame
  b.add_packet(kFrameTicks, 4, 40 * kMs);  // next frame: not a pause inside one
  EXPECT_EQ(b.burst_gap_ns(), 10 * kMs);
  EXPECT_EQ(b.frame_end_wait_ns(), 15 * kMs);
}

TEST(JitterBudget, ALinkThatGotBetterIsTrustedAfterTheWindow) {
  JitterBudget b(settings(false));
  stream(
      b, [](int k) { return k == 10 ? 80 : 0; }, 60);
  EXPECT_GT(b.latency_ms(), 80);
  uint16_t seq = 1000;
  for (int k = 60; k < 150; ++k)  // 3 s more, steady
    for (int p = 0; p < 10; ++p)
      b.add_packet(uint32_t(k) * kFrameTicks, seq++, int64_t(k) * 100 * kMs / 3 + p * 100'000);
  EXPECT_EQ(b.latency_ms(), 20);
}

}  // namespace
}  // namespace hd::drivers
