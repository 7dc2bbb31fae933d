// GigE stream sizing: socket buffer for 100 ms of frames, the Aravis buffer pool for the frame
// retention, and the retention clamp, with the numbers open() uses.
#include "drivers/gige/stream_sizing.h"

#include <gtest/gtest.h>

namespace hd::drivers {

constexpr std::size_t kVga8 = 640 * 480;  // one Mono8 640x480 frame: 307200 bytes

TEST(StreamSizing, SocketBufferHoldsFourFramesAtLowRates) {
  EXPECT_EQ(socket_buffer_bytes_for(0, kVga8, 30.0), 4 * 307'200);  // 100 ms = 3 frames < 4
  EXPECT_EQ(socket_buffer_bytes_for(0, kVga8, 25.0), 4 * 307'200);  // 2.5 -> 3 frames < 4
}

TEST(StreamSizing, SocketBufferHolds100MsOfFramesAtHighRates) {
  EXPECT_EQ(socket_buffer_bytes_for(0, kVga8, 60.0), 6 * 307'200);
  EXPECT_EQ(socket_buffer_bytes_for(0, kVga8, 120.0), 12 * 307'200);
}

TEST(StreamSizing, SocketBufferIsAtMost64MiBAndAConfiguredOneWins) {
  const std::size_t rgb_4k = 4096 * 2160 * 3;  // 26.5 MB a frame
  EXPECT_EQ(socket_buffer_bytes_for(0, rgb_4k, 30.0), 64 << 20);
  EXPECT_EQ(socket_buffer_bytes_for(1 << 20, rgb_4k, 30.0), 1 << 20);
}

TEST(StreamSizing, BufferCountCoversTheFramesInFlightDuringRetentionPlusFour) {
  EXPECT_EQ(buffer_count_for(0, 30.0, 300'000'000), 13);   // 9 in flight + 4
  EXPECT_EQ(buffer_count_for(0, 60.0, 300'000'000), 22);   // 18 + 4
  EXPECT_EQ(buffer_count_for(0, 120.0, 300'000'000), 40);  // 36 + 4
  EXPECT_EQ(buffer_count_for(0, 25.0, 300'000'000), 12);   // 7.5 -> 8, + 4
}

TEST(StreamSizing, BufferCountIsAtLeast8AndAConfiguredOneWins) {
  EXPECT_EQ(buffer_count_for(0, 10.0, 100'000'000), 8);  // 1 + 4 would be too few
  EXPECT_EQ(buffer_count_for(3, 120.0, 300'000'000), 3);
}

TEST(StreamSizing, FrameRetentionIsInMicrosecondsBetween1MsAnd10S) {
  EXPECT_EQ(frame_retention_us_for(300'000'000), 300'000u);
  EXPECT_EQ(frame_retention_us_for(100'000), 1'000u);              // 0.1 ms -> 1 ms
  EXPECT_EQ(frame_retention_us_for(60'000'000'000), 10'000'000u);  // 60 s -> 10 s
}

}  // namespace hd::drivers
