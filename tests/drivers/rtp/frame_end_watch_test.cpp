// FrameEndWatch: a frame whose marked last packet did not come is asked for after the wait.
#include "drivers/rtp/frame_end_watch.h"

#include <gtest/gtest.h>

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;

FrameEndWatch::Settings settings() {
  FrameEndWatch::Settings s;
  s.wait_ns = 3 * kMs;
  s.retry_ns = 10 * kMs;
  s.max_requests = 3;
  return s;
}

TEST(FrameEndWatch, AFrameThatEndedWithItsMarkerAwaitsNothing) {
  FrameEndWatch w(settings());
  w.on_packet(10, false, 0);
  w.on_packet(11, true, 100'000);
  EXPECT_EQ(w.due_ns(), 0);
  EXPECT_FALSE(w.on_due(100 * kMs));
  EXPECT_EQ(w.requests(), 0u);
}

TEST(FrameEndWatch, AMissingLastPacketIsAskedForTheWaitAfterTheNewest) {
  FrameEndWatch w(settings());
  w.on_packet(10, false, 0);
  w.on_packet(11, false, 1 * kMs);
  EXPECT_EQ(w.due_ns(), 4 * kMs);
  EXPECT_FALSE(w.on_due(4 * kMs - 1));
  const auto asked = w.on_due(4 * kMs);
  ASSERT_TRUE(asked);
  EXPECT_EQ(*asked, 12);
  EXPECT_EQ(w.due_ns(), 14 * kMs);  // again after retry_ns if its repair does not come
}

TEST(FrameEndWatch, TheRepairWithTheMarkerEndsTheWaitAndOneWithoutAsksForTheNext) {
  FrameEndWatch w(settings());
  w.on_packet(65535, false, 0);
  ASSERT_TRUE(w.on_due(3 * kMs));
  w.on_packet(0, false, 5 * kMs);  // the repair (wrapped), not the last either
  const auto next = w.on_due(8 * kMs);
  ASSERT_TRUE(next);
  EXPECT_EQ(*next, 1);
  w.on_packet(1, true, 9 * kMs);
  EXPECT_EQ(w.due_ns(), 0);
}

TEST(FrameEndWatch, AsksAtMostMaxRequestsTimes) {
  FrameEndWatch w(settings());
  w.on_packet(7, false, 0);
  EXPECT_TRUE(w.on_due(3 * kMs));
  EXPECT_TRUE(w.on_due(13 * kMs));
  EXPECT_TRUE(w.on_due(23 * kMs));
  EXPECT_EQ(w.due_ns(), 0);
  EXPECT_FALSE(w.on_due(100 * kMs));
  EXPECT_EQ(w.requests(), 3u);
}

TEST(FrameEndWatch, AnOlderPacketDoesNotMoveTheWatch) {
  FrameEndWatch w(settings());
  w.on_packet(20, false, 0);
  w.on_packet(18, true, 1 * kMs);  // a repair of an earlier gap: the jitter buffer's
  EXPECT_EQ(w.due_ns(), 3 * kMs);
}

}  // namespace
}  // namespace hd::drivers
