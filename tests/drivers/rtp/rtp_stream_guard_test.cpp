// RtpStreamGuard: which packets of the media payload type belong to the live stream (one SSRC,
// sequence numbers and RTP times a live sender sends), by hand and under random numbers.
#include "drivers/rtp/rtp_stream_guard.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;
constexpr int64_t kSilenceNs = 500 * kMs;

RtpPacketView packet(uint32_t ssrc, uint16_t seq, uint32_t ts) {
  RtpPacketView p;
  p.payload_type = 96;
  p.ssrc = ssrc;
  p.sequence = seq;
  p.timestamp = ts;
  return p;
}

TEST(RtpStreamGuard, AStreamWithLossReorderingAndWrapPasses) {
  RtpStreamGuard g(kSilenceNs);
  int64_t t = 1'000 * kMs;
  uint32_t ts = 4'000'000'000u;
  uint16_t seq = 65'500;
  for (int i = 0; i < 200; ++i, ++seq, t += 3 * kMs) {
    if (i % 7 == 0) ts += 3000;  // a frame every 7 packets, 30 Hz
    ASSERT_EQ(g.check(packet(1, seq, ts), t), RtpPacketError::kNone) << i;
  }
  // A loss of kMaxSequenceJump - 1 packets, then one reordered from before it.
  seq = uint16_t(seq + RtpStreamGuard::kMaxSequenceJump - 1);
  EXPECT_EQ(g.check(packet(1, seq, ts + 3000), t), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(1, uint16_t(seq - 100), ts - 3000), t), RtpPacketError::kNone);
  EXPECT_EQ(g.starts(), 1u);
  EXPECT_EQ(g.resyncs(), 0u);
}

TEST(RtpStreamGuard, AWildSequenceNumberIsRefusedAndTheStreamGoesOn) {
  RtpStreamGuard g(kSilenceNs);
  EXPECT_EQ(g.check(packet(1, 1000, 90'000), 0), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(1, 1001, 90'000), kMs), RtpPacketError::kNone);
  // Ahead by more than a loss burst, or behind by more than reordering.
  EXPECT_EQ(g.check(packet(1, 1001 + RtpStreamGuard::kMaxSequenceJump + 1, 90'000), 2 * kMs),
            RtpPacketError::kSequenceJump);
  EXPECT_EQ(g.check(packet(1, 30'000, 90'000), 2 * kMs), RtpPacketError::kSequenceJump);
  EXPECT_EQ(g.check(packet(1, 1001 - RtpStreamGuard::kMaxMisorder - 1, 90'000), 2 * kMs),
            RtpPacketError::kSequenceJump);
  EXPECT_EQ(g.check(packet(1, 1002, 93'000), 3 * kMs), RtpPacketError::kNone);
  EXPECT_EQ(g.resyncs(), 0u);
}

TEST(RtpStreamGuard, TwoConsecutivePacketsInANewNumberingAreTaken) {
  RtpStreamGuard g(kSilenceNs);
  EXPECT_EQ(g.check(packet(1, 1000, 90'000), 0), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(1, 20'000, 93'000), kMs), RtpPacketError::kSequenceJump);
  EXPECT_EQ(g.check(packet(1, 20'001, 93'000), 2 * kMs), RtpPacketError::kNone);  // confirmed
  EXPECT_EQ(g.resyncs(), 1u);
  EXPECT_EQ(g.check(packet(1, 1001, 93'000), 3 * kMs), RtpPacketError::kSequenceJump);  // the old
  EXPECT_EQ(g.check(packet(1, 20'002, 96'000), 4 * kMs), RtpPacketError::kNone);
  // A follower with a wild RTP time confirms nothing.
  EXPECT_EQ(g.check(packet(1, 50'000, 96'000), 5 * kMs), RtpPacketError::kSequenceJump);
  EXPECT_EQ(g.check(packet(1, 50'001, 96'000 + 10 * 90'000), 6 * kMs),
            RtpPacketError::kSequenceJump);
  EXPECT_EQ(g.resyncs(), 1u);
}

TEST(RtpStreamGuard, AnRtpTimeFarFromTheArrivalTimeIsRefused) {
  RtpStreamGuard g(kSilenceNs);
  EXPECT_EQ(g.check(packet(1, 1, 1'000'000), 0), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(1, 2, 1'000'000 + 2 * 90'000), kMs), RtpPacketError::kRtpTimeJump);
  EXPECT_EQ(g.check(packet(1, 2, 1'000'000 - 2 * 90'000), kMs), RtpPacketError::kRtpTimeJump);
  EXPECT_EQ(g.check(packet(1, 2, 0x80000000u), kMs), RtpPacketError::kRtpTimeJump);
  // 0.4 s without packets (below the silence): the RTP time may be 0.4 s + 1 s ahead.
  EXPECT_EQ(g.check(packet(1, 2, 1'000'000 + 126'000 - 100), 400 * kMs), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(1, 3, 1'000'000 + 126'000 - 90'000), 401 * kMs),
            RtpPacketError::kNone);  // behind the highest by up to 1 s
}

TEST(RtpStreamGuard, AnotherSsrcIsTakenOnlyAfterTheStreamFellSilent) {
  RtpStreamGuard g(kSilenceNs);
  EXPECT_EQ(g.check(packet(1, 1, 0), 0), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(2, 500, 77), 100 * kMs), RtpPacketError::kOtherSsrc);
  EXPECT_EQ(g.check(packet(1, 2, 3000), 200 * kMs), RtpPacketError::kNone);
  // Silent for the stall timeout: a restarted sender (new SSRC, new numbers) starts afresh.
  EXPECT_EQ(g.check(packet(2, 40'000, 123'456'789), 700 * kMs), RtpPacketError::kNone);
  EXPECT_EQ(g.check(packet(1, 3, 6000), 701 * kMs), RtpPacketError::kOtherSsrc);
  EXPECT_EQ(g.check(packet(2, 40'001, 123'456'789), 702 * kMs), RtpPacketError::kNone);
  EXPECT_EQ(g.starts(), 2u);
}

// Random packets among a live stream: the stream keeps passing (at most the packets behind a
// stray one taken within the jump window are at risk), and a random number beyond the windows
// passes only when the next random one happens to follow it (a renumbering, ~1 in 65536).
TEST(RtpStreamGuard, RandomNumbersAmongAStreamNeverPassAWildJump) {
  RtpStreamGuard g(kSilenceNs);
  std::mt19937_64 rng(20261202);
  uint16_t seq = 17;
  uint32_t ts = 12345;
  int64_t t = 0;
  uint64_t clean = 0, clean_refused = 0, wild = 0, wild_taken = 0;
  ASSERT_EQ(g.check(packet(1, seq, ts), t), RtpPacketError::kNone);  // the stream starts
  for (int i = 0; i < 1'000'000; ++i) {
    t += kMs;
    if (rng() % 100 < 40) {  // a mutated packet: any sequence number, sometimes any RTP time
      ++wild;
      const uint16_t s = uint16_t(rng());
      const uint32_t r = rng() % 4 == 0 ? uint32_t(rng()) : ts;
      const uint64_t resyncs = g.resyncs();
      if (g.check(packet(1, s, r), t) == RtpPacketError::kNone) {
        ++wild_taken;
        // Beyond the windows only as the second of two consecutive packets (a renumbering).
        const int d = int16_t(uint16_t(s - seq));
        if (d > RtpStreamGuard::kMaxSequenceJump + RtpStreamGuard::kMaxMisorder ||
            d < -2 * RtpStreamGuard::kMaxMisorder) {
          EXPECT_EQ(g.resyncs(), resyncs + 1) << i << ": " << s << " among " << seq;
        }
      }
      continue;
    }
    ++clean;
    ++seq;
    if (seq % 7 == 0) ts += 3000;
    if (g.check(packet(1, seq, ts), t) != RtpPacketError::kNone) ++clean_refused;
  }
  std::printf("%llu clean packets, %llu refused; %llu random ones, %llu taken\n",
              static_cast<unsigned long long>(clean),
              static_cast<unsigned long long>(clean_refused), static_cast<unsigned long long>(wild),
              static_cast<unsigned long long>(wild_taken));
  // Only random numbers within the windows pass (about (2 * 128 + 1) / 65536 of them).
  EXPECT_LT(wild_taken, wild / 100);
  EXPECT_LT(clean_refused, clean / 1000);
  EXPECT_EQ(g.starts(), 1u);
}

}  // namespace
}  // namespace hd::drivers
