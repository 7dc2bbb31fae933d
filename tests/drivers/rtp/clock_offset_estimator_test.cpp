// The sender-clock offset from RTCP sender reports and round trips, against closed forms: a
// sender clock shifted by a known amount, one-way delays chosen by hand.
#include "drivers/rtp/clock_offset_estimator.h"

#include <gtest/gtest.h>

#include <random>

#include "drivers/rtp/rtp_frame_stamp.h"

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;
// Station mono = sender unix + kOffset (a sender clock 2.5 s ahead of this host's realtime, and
// realtime - monotonic of 1.7e18 ns).
constexpr int64_t kOffset = -1'700'000'000'000'000'000LL - 2'500 * kMs;

TEST(ClockOffsetEstimator, UnmeasuredUntilItHasASenderReportAndARoundTrip) {
  ClockOffsetEstimator e(0.0);
  EXPECT_EQ(e.mapping(0).kind, ClockMapping::Kind::kUnmeasured);
  e.add_sender_report(10'000 * kMs - kOffset, 10'000 * kMs + 1 * kMs);
  EXPECT_EQ(e.mapping(0).kind, ClockMapping::Kind::kUnmeasured);
  EXPECT_EQ(e.mapping(0).uncertainty_ns, -1);
  e.add_round_trip(2 * kMs);
  const ClockMapping m = e.mapping(10'000 * kMs);
  EXPECT_EQ(m.kind, ClockMapping::Kind::kMeasured);
  EXPECT_EQ(m.samples, 2u);
  // 1 ms one way, 2 ms round trip: the symmetric guess is exact.
  EXPECT_EQ(m.offset_ns, kOffset);
  EXPECT_EQ(m.uncertainty_ns, 1 * kMs);
}

TEST(ClockOffsetEstimator, TakesTheLeastDelayedReportAndTheSmallestRoundTrip) {
  ClockOffsetEstimator e(0.0);
  const int64_t delays_ms[] = {7, 3, 12, 4, 9};
  const int64_t rtts_ms[] = {15, 8, 25, 6, 19};
  int64_t t = 50'000 * kMs;
  for (int i = 0; i < 5; ++i, t += 1'000 * kMs) {
    e.add_sender_report(t - kOffset, t + delays_ms[i] * kMs);
    e.add_round_trip(rtts_ms[i] * kMs);
  }
  const ClockMapping m = e.mapping(t);
  // min(arrival - sent) = kOffset + 3 ms, smallest round trip 6 ms: kOffset + 3 - 3.
  EXPECT_EQ(m.offset_ns, kOffset);
  EXPECT_EQ(m.uncertainty_ns, 3 * kMs);
  EXPECT_EQ(m.round_trip_ns, 6 * kMs);
}

TEST(ClockOffsetEstimator, TheTruthIsWithinTheUncertaintyWhateverWayTheDelaySplits) {
  std::mt19937_64 rng(12);
  for (int trial = 0; trial < 1000; ++trial) {
    ClockOffsetEstimator e(0.0);
    int64_t t = 1'000 * kMs;
    for (std::size_t i = 0; i < ClockOffsetEstimator::kWindow; ++i, t += 1'000 * kMs) {
      // A round trip of 1..20 ms split anyhow: the report's one-way delay is 0..rtt.
      const int64_t rtt = kMs + int64_t(rng() % uint64_t(19 * kMs));
      const int64_t one_way = int64_t(rng() % uint64_t(rtt + 1));
      e.add_sender_report(t - kOffset, t + one_way);
      e.add_round_trip(rtt);
    }
    const ClockMapping m = e.mapping(t);
    ASSERT_LE(std::llabs(m.offset_ns - kOffset), m.uncertainty_ns) << "trial " << trial;
  }
}

TEST(ClockOffsetEstimator, OldReportsLeaveTheWindowAndDriftWidensTheUncertainty) {
  ClockOffsetEstimator e(100.0);  // 100 ppm: 0.1 ms per second of age
  int64_t t = 0;
  e.add_sender_report(t - kOffset, t);  // no delay at all: the best report
  e.add_round_trip(4 * kMs);
  EXPECT_EQ(e.mapping(t).offset_ns, kOffset - 2 * kMs);
  EXPECT_EQ(e.mapping(t + 10'000 * kMs).uncertainty_ns, 2 * kMs + 1 * kMs);  // 10 s old
  for (std::size_t i = 0; i < ClockOffsetEstimator::kWindow; ++i) {
    t += 1'000 * kMs;
    e.add_sender_report(t - kOffset, t + 5 * kMs);
  }
  // The undelayed report is gone: the newest kWindow all had 5 ms.
  EXPECT_EQ(e.mapping(t).offset_ns, kOffset + 5 * kMs - 2 * kMs);
}

TEST(ClockOffsetEstimator, MediaPacketsCapAReportDelayedBeyondItsRoundTrip) {
  ClockOffsetEstimator e(0.0);
  int64_t t = 1'000 * kMs;
  // A busy machine: the report took 30 ms although the round trip says 2 ms.
  e.add_sender_report(t - kOffset, t + 30 * kMs);
  e.add_round_trip(2 * kMs);
  EXPECT_EQ(e.mapping(t).offset_ns, kOffset + 29 * kMs);
  EXPECT_FALSE(e.mapping(t).bounded_by_packets);
  // Frames captured 4..9 ms before they arrived: the offset is at most kOffset + 4 ms.
  for (int64_t delay_ms : {9, 4, 6}) {
    t += 33 * kMs;
    e.add_packet(t - delay_ms * kMs - kOffset, t);
  }
  const ClockMapping m = e.mapping(t);
  EXPECT_TRUE(m.bounded_by_packets);
  EXPECT_EQ(m.offset_ns, kOffset + 4 * kMs);
  // The report's own 1 ms, and the 25 ms it was shown off by.
  EXPECT_EQ(m.uncertainty_ns, 1 * kMs + 25 * kMs);
  EXPECT_LE(std::llabs(m.offset_ns - kOffset), m.uncertainty_ns);
  // A bound above the reports' estimate changes nothing.
  ClockOffsetEstimator idle(0.0);
  idle.add_sender_report(t - kOffset, t + 1 * kMs);
  idle.add_round_trip(2 * kMs);
  idle.add_packet(t - 5 * kMs - kOffset, t);
  EXPECT_EQ(idle.mapping(t).offset_ns, kOffset);
  EXPECT_FALSE(idle.mapping(t).bounded_by_packets);
}

TEST(ClockOffsetEstimator, APacketBoundLastsOneToTwoSpans) {
  ClockOffsetEstimator e(0.0);
  constexpr int64_t kSpan = ClockOffsetEstimator::kBoundSpanNs;
  int64_t t = 10'000 * kMs;
  e.add_sender_report(t - kOffset, t + 30 * kMs);
  e.add_round_trip(2 * kMs);
  e.add_packet(t - 3 * kMs - kOffset, t);  // starts a span at t
  EXPECT_EQ(e.mapping(t + kSpan - 1).offset_ns, kOffset + 3 * kMs);
  // The next span: the first one's bound is still the previous span's.
  e.add_packet(t + kSpan - 8 * kMs - kOffset, t + kSpan);
  EXPECT_EQ(e.mapping(t + kSpan).offset_ns, kOffset + 3 * kMs);
  // A third span: only the second's bound (8 ms) is left.
  e.add_packet(t + 2 * kSpan - 10 * kMs - kOffset, t + 2 * kSpan);
  EXPECT_EQ(e.mapping(t + 2 * kSpan).offset_ns, kOffset + 8 * kMs);
  // No packet for two spans: no bound, the reports' estimate again.
  EXPECT_EQ(e.mapping(t + 4 * kSpan).offset_ns, kOffset + 29 * kMs);
  EXPECT_FALSE(e.mapping(t + 4 * kSpan).bounded_by_packets);
}

TEST(ClockOffsetEstimator, RefusesAReportArrivingBeforeTheNewestAndANegativeRoundTrip) {
  ClockOffsetEstimator e(0.0);
  e.add_sender_report(0, 5'000 * kMs);
  e.add_sender_report(0, 4'000 * kMs);
  e.add_round_trip(-1);
  EXPECT_EQ(e.refused(), 2u);
  EXPECT_EQ(e.mapping(0).samples, 1u);
}

TEST(ClockOffsetEstimator, TheWordsGiveTheOffsetBetweenTheSitesNotBetweenTwoClocksOfThisHost) {
  // kOffset: a sender clock 2.5 s ahead of this host's realtime, realtime - mono = 1.7e18 ns.
  constexpr int64_t kHostRealtimeMinusMono = 1'700'000'000'000'000'000LL;
  ClockOffsetEstimator e(0.0);
  e.add_sender_report(10'000 * kMs - kOffset, 10'000 * kMs + 1 * kMs);
  e.add_round_trip(2 * kMs);
  const ClockMapping m = e.mapping(10'000 * kMs);
  EXPECT_EQ(sites_offset_ns(m, kHostRealtimeMinusMono), 2'500 * kMs);
  EXPECT_EQ(describe(m, kHostRealtimeMinusMono),
            "sender's CLOCK_REALTIME - this station's = +2500.000 ms +- 1.000 ms, measured from "
            "2 RTCP sender reports and round trips (smallest round trip 2.000 ms)");
  ClockMapping synced;
  synced.kind = ClockMapping::Kind::kSynchronized;
  synced.offset_ns = -kHostRealtimeMinusMono;
  synced.uncertainty_ns = 3 * kMs / 2;
  EXPECT_EQ(describe(synced, kHostRealtimeMinusMono),
            "both sites' CLOCK_REALTIME declared synchronized (chrony/PTP, or one host): "
            "sender's - this station's = +0.000 ms +- 1.500 ms as stated, not measured");
  EXPECT_NE(describe(ClockMapping{}, kHostRealtimeMinusMono).find("not measured yet"),
            std::string::npos);
}

TEST(ClockOffsetEstimator, RoundTripFromAReportBlockIsArrivalMinusLsrMinusDlsr) {
  // RFC 3550 A.8's example: arrival 46864.250 s, LSR 46853.125 s, DLSR 5.250 s: 5.875 s.
  const uint32_t arrival = (46864u << 16) | 0x4000u;
  const uint32_t lsr = (46853u << 16) | 0x2000u;
  const uint32_t dlsr = (5u << 16) | 0x4000u;
  EXPECT_EQ(round_trip_from_report_block(arrival, lsr, dlsr), 5'875 * kMs);
  EXPECT_EQ(round_trip_from_report_block(arrival, 0, dlsr), -1);  // no sender report seen yet
  EXPECT_EQ(round_trip_from_report_block(lsr, arrival, 0), -1);   // negative: a clock step
  // Across the 32-bit wrap of the compact form.
  EXPECT_EQ(round_trip_from_report_block(0x00000100u, 0xFFFFFF00u, 0),
            (0x200LL * 1'000'000'000LL + (1 << 15)) >> 16);
  const int64_t unix_ns = 1'796'169'600'500'000'000LL;
  EXPECT_EQ(compact_ntp(unix_ns), uint32_t(unix_ns_to_ntp64(unix_ns) >> 16));
  EXPECT_EQ(compact_ntp(unix_ns) & 0xFFFFu, 0x8000u);  // half a second
}

}  // namespace
}  // namespace hd::drivers
