// AccessUnitPts: each access unit keeps its own PTS at the depayloader's input, whatever the
// jitter buffer's clamp gave it; packets of one access unit share it; a jump back of a second or
// more (a new stream) is taken as it is.
#include "drivers/rtp/access_unit_pts.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>

namespace hd::drivers {
namespace {

constexpr uint64_t kFrameNs = 33'333'333;

TEST(AccessUnitPts, PtsThatGoForwardAreKeptAndAnAccessUnitsPacketsShareTheFirstOnes) {
  AccessUnitPts a;
  EXPECT_EQ(a.next(3000, kFrameNs), kFrameNs);
  EXPECT_EQ(a.next(3000, kFrameNs + 5), kFrameNs);  // a later packet of the same frame
  EXPECT_EQ(a.next(6000, 2 * kFrameNs), 2 * kFrameNs);
  EXPECT_EQ(a.nudged(), 0u);
}

TEST(AccessUnitPts, AFrameGivenThePreviousFramesPtsGetsItsOwnJustAfter) {
  AccessUnitPts a;
  // The jitter buffer's clamp: frames 2 and 3 come out with frame 1's PTS, frame 4 on time.
  const uint64_t in[4][2] = {
      {3000, kFrameNs}, {6000, kFrameNs}, {9000, kFrameNs}, {12000, 4 * kFrameNs}};
  std::set<uint64_t> seen;
  uint64_t previous = 0;
  for (const auto& p : in) {
    const uint64_t out = a.next(static_cast<uint32_t>(p[0]), p[1]);
    EXPECT_GT(out, previous);
    EXPECT_LE(out - p[1], 2 * AccessUnitPts::kNudgeNs);  // moved by microseconds, not a frame
    EXPECT_TRUE(seen.insert(out).second);
    EXPECT_EQ(a.next(static_cast<uint32_t>(p[0]), p[1]), out);  // its other packets: the same
    previous = out;
  }
  EXPECT_EQ(a.nudged(), 2u);
}

TEST(AccessUnitPts, AJumpBackOfASecondIsANewStreamTakenAsItIs) {
  AccessUnitPts a;
  a.next(3000, 5'000'000'000);
  EXPECT_EQ(a.next(100, 3'000'000'000), 3'000'000'000u);
  EXPECT_EQ(a.nudged(), 0u);
}

}  // namespace
}  // namespace hd::drivers
