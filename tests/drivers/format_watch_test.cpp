// FormatWatch: one kLost per loss, a kRestored only after a kLost, and forget() silent.
#include "drivers/format_watch.h"

#include <gtest/gtest.h>

#include <vector>

namespace hd::drivers {
namespace {

const CameraFormat kExpected{640, 480, PixelFormat::kRgba8, 30.0};
const CameraFormat kSeen{320, 240, PixelFormat::kRgba8, 0.0};

std::vector<FormatEvent> drain(FormatWatch& w) {
  std::vector<FormatEvent> out;
  FormatEvent e;
  while (w.pop(e)) out.push_back(e);
  return out;
}

TEST(FormatWatch, ARunOfWrongFramesLeavesOneLostEvent) {
  FormatWatch w;
  EXPECT_TRUE(w.lost(10, FormatEventCause::kFrame, kExpected, kSeen));
  EXPECT_FALSE(w.lost(20, FormatEventCause::kFrame, kExpected, kSeen));
  EXPECT_FALSE(w.lost(30, FormatEventCause::kSourceChange, kExpected, kSeen));
  EXPECT_TRUE(w.is_lost());
  const std::vector<FormatEvent> ev = drain(w);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].time_ns, 10);
  EXPECT_EQ(ev[0].kind, FormatEventKind::kLost);
  EXPECT_EQ(ev[0].cause, FormatEventCause::kFrame);
  EXPECT_EQ(ev[0].expected.width_px, 640);
  EXPECT_EQ(ev[0].seen.width_px, 320);
  EXPECT_EQ(ev[0].seen.height_px, 240);
}

TEST(FormatWatch, RestoredFollowsOnlyALoss) {
  FormatWatch w;
  EXPECT_FALSE(w.restored(5, FormatEventCause::kFrame, kExpected));
  EXPECT_TRUE(drain(w).empty());
  w.lost(10, FormatEventCause::kReconnect, kExpected, kSeen);
  EXPECT_TRUE(w.restored(40, FormatEventCause::kReconnect, kExpected));
  EXPECT_FALSE(w.restored(50, FormatEventCause::kReconnect, kExpected));
  EXPECT_FALSE(w.is_lost());
  const std::vector<FormatEvent> ev = drain(w);
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_EQ(ev[0].kind, FormatEventKind::kLost);
  EXPECT_EQ(ev[1].kind, FormatEventKind::kRestored);
  EXPECT_EQ(ev[1].time_ns, 40);
  EXPECT_EQ(ev[1].seen.width_px, kExpected.width_px);  // it delivers what was negotiated again
}

TEST(FormatWatch, ANewNegotiationForgetsTheLossWithoutAnEvent) {
  FormatWatch w;
  w.lost(10, FormatEventCause::kFrame, kExpected, kSeen);
  drain(w);
  w.forget();
  EXPECT_FALSE(w.is_lost());
  EXPECT_FALSE(w.restored(20, FormatEventCause::kFrame, kExpected));
  EXPECT_TRUE(drain(w).empty());
  EXPECT_TRUE(w.lost(30, FormatEventCause::kFrame, kExpected, kSeen));  // a new loss is news
}

TEST(FormatWatch, UnreadEventsBeyondTheRingAreCountedNotLost) {
  FormatWatch w;
  constexpr int kPairs = 40;  // 80 events into a ring of 64
  for (int i = 0; i < kPairs; ++i) {
    w.lost(2 * i, FormatEventCause::kFrame, kExpected, kSeen);
    w.restored(2 * i + 1, FormatEventCause::kFrame, kExpected);
  }
  const std::size_t read = drain(w).size();
  EXPECT_EQ(read + w.overflowed(), 2u * kPairs);
  EXPECT_GT(w.overflowed(), 0u);
}

}  // namespace
}  // namespace hd::drivers
