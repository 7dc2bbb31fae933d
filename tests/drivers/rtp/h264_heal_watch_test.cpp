// H264HealWatch: which access units' pictures are whole after losses (sequence gaps, lost
// events), healed by an IDR or by a recovery point's count of intact access units, and when a
// key frame is asked for (only for a stream that heals by IDR).
#include "drivers/rtp/h264_heal_watch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <initializer_list>

namespace hd::drivers {
namespace {

constexpr uint64_t kFrame = 33'333'333;

// Access units of 3 packets each (the last with the marker), sequence numbers from `seq`.
struct Stream {
  H264HealWatch w;
  uint16_t seq = 65530;  // wraps within the tests
  uint64_t n = 0;
  // Sends frame n's packets except those in `drop` (0..2), then judges it (no lost event when all
  // three are dropped: the gap alone tells). A dropped last packet
  // is known only from the jitter buffer's lost event (the depayloader outputs the access unit
  // without its marker when that event or the next packet comes): sent before judging.
  H264HealWatch::Verdict frame(H264AccessUnitInfo info = {}, std::initializer_list<int> drop = {}) {
    const uint64_t pts = ++n * kFrame;
    for (int p = 0; p < 3; ++p, ++seq) {
      if (std::find(drop.begin(), drop.end(), p) != drop.end()) continue;
      w.packet(seq, pts, p == 2, p == 0);  // the first packet begins the picture
    }
    if (drop.size() == 3) return {};  // a whole frame lost: nothing out of the depayloader
    if (std::find(drop.begin(), drop.end(), 2) != drop.end()) w.lost();
    return w.access_unit(pts, info);
  }
};

H264AccessUnitInfo idr() {
  H264AccessUnitInfo i;
  i.idr = true;
  return i;
}
H264AccessUnitInfo recovery(uint32_t cnt) {
  H264AccessUnitInfo i;
  i.recovery_frame_cnt = cnt;
  return i;
}

TEST(H264HealWatch, DamagedFromTheStartUntilAnIdrThenAfterAGapUntilTheNextIdr) {
  Stream s;
  EXPECT_FALSE(s.frame().whole);  // nothing to predict from yet
  EXPECT_TRUE(s.frame(idr()).whole);
  EXPECT_TRUE(s.frame().whole);
  EXPECT_FALSE(s.frame({}, {1}).whole);  // a hole inside
  EXPECT_FALSE(s.frame().whole);         // predicted from it
  EXPECT_FALSE(s.w.heals_by_refresh());
  EXPECT_TRUE(s.frame(idr()).whole);
  EXPECT_FALSE(s.frame(idr(), {0}).whole);  // an IDR that lost its head is no IDR
}

TEST(H264HealWatch, ARecoveryPointHealsRecoveryFrameCntIntactFramesLater) {
  Stream s;
  s.frame(idr());
  s.frame(recovery(3));  // a refresh stream: seen while whole
  EXPECT_TRUE(s.w.heals_by_refresh());
  EXPECT_EQ(s.w.refresh_frames(), 4);
  EXPECT_FALSE(s.frame({}, {2}).whole);  // lost its last packet (the marker)
  EXPECT_FALSE(s.frame().whole);
  EXPECT_FALSE(s.frame(recovery(3)).whole);  // frame 0 of the sweep
  EXPECT_FALSE(s.frame().whole);             // 1
  EXPECT_FALSE(s.frame().whole);             // 2
  EXPECT_TRUE(s.frame().whole);              // 3: whole
  EXPECT_TRUE(s.frame().whole);
  // recovery_frame_cnt 0: whole at once.
  s.frame({}, {0});
  EXPECT_TRUE(s.frame(recovery(0)).whole);
}

TEST(H264HealWatch, TheRecoveryPointMustBeginAfterTheLoss) {
  Stream s;
  s.frame(idr());
  // The recovery point's own access unit lost a packet: it heals nothing.
  EXPECT_FALSE(s.frame(recovery(1), {1}).whole);
  EXPECT_FALSE(s.frame().whole);
  EXPECT_FALSE(s.frame().whole);
  // One that lost its head.
  EXPECT_FALSE(s.frame(recovery(1), {0}).whole);
  EXPECT_FALSE(s.frame().whole);
  // A gap right before one whose first packet begins it: the lost packets were not its own.
  s.seq += 2;
  EXPECT_FALSE(s.frame(recovery(1)).whole);
  EXPECT_TRUE(s.frame().whole);
  // The same after whole frames were lost: the gap alone damages the stream.
  s.frame({}, {0, 1, 2});
  EXPECT_FALSE(s.frame().whole);
  EXPECT_TRUE(s.frame(idr()).whole);
  s.frame({}, {0, 1, 2});
  EXPECT_TRUE(s.frame(idr()).whole);  // an IDR right after the gap, all of it there
  // A loss during the countdown starts over.
  s.frame({}, {1});
  EXPECT_FALSE(s.frame(recovery(2)).whole);
  EXPECT_FALSE(s.frame().whole);
  EXPECT_FALSE(s.frame({}, {2}).whole);
  EXPECT_FALSE(s.frame().whole);
  EXPECT_FALSE(s.frame().whole);
  EXPECT_FALSE(s.frame(recovery(2)).whole);
  EXPECT_FALSE(s.frame().whole);
  EXPECT_TRUE(s.frame().whole);
}

TEST(H264HealWatch, ALostEventDamagesTheStreamAndTheAccessUnitInProgress) {
  Stream s;
  s.frame(idr());
  // Two packets of the next frame came, then the jitter buffer gave up on the third.
  const uint64_t pts = ++s.n * kFrame;
  s.w.packet(s.seq++, pts, false, true);
  s.w.packet(s.seq++, pts, false, false);
  s.w.lost();
  ++s.seq;
  EXPECT_FALSE(s.w.access_unit(pts, {}).whole);
  EXPECT_FALSE(s.frame().whole);
  EXPECT_TRUE(s.frame(idr()).whole);
  // A malformed access unit is not known to be whole either.
  H264AccessUnitInfo bad;
  bad.malformed = true;
  EXPECT_FALSE(s.frame(bad).whole);
}

TEST(H264HealWatch, AsksForAKeyFrameOnEachLossUnlessTheStreamHealsByRefresh) {
  Stream s;
  EXPECT_TRUE(s.frame().request_key_frame);  // damaged from the start: once
  EXPECT_FALSE(s.frame().request_key_frame);
  EXPECT_FALSE(s.frame(idr()).request_key_frame);
  EXPECT_TRUE(s.frame({}, {1}).request_key_frame);  // a loss
  EXPECT_FALSE(s.frame().request_key_frame);
  EXPECT_TRUE(s.frame({}, {0}).request_key_frame);  // another, before the IDR came
  EXPECT_TRUE(s.frame(idr()).whole);
  // A stream that heals by refresh: never (the encoder would answer with another sweep).
  s.frame(recovery(4));
  for (int i = 0; i < 40; ++i) EXPECT_FALSE(s.frame({}, {i % 3}).request_key_frame) << i;
}

}  // namespace
}  // namespace hd::drivers
