// The network camera against a real peer: gst-launch-1.0's plain RTP H.264 sender on loopback.
#include "drivers/rtp/rtp_camera.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

using testing::GstLaunch;

// Polls `f` until it holds, for up to 60 s (waits for the peer; asserts nothing about speed).
RtpReceiveConfig config_for(uint16_t port) {
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", port};
  return c;
}

void send_datagram(uint16_t port, const std::vector<uint8_t>& bytes) {
  const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::sendto(s, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
  ::close(s);
}

TEST(RtpCamera, ThePlainSendersFramesArriveDecodedAtTheirSizeStampedWithTheirArrival) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpCamera cam(config_for(port));
  EXPECT_EQ(cam.id(), "rtp://127.0.0.1:" + std::to_string(port));
  // videotestsrc's default size: 320x240.
  const FormatNegotiation n = cam.negotiate({320, 240, {}, 0.0});
  EXPECT_FALSE(n.delivered.known());
  EXPECT_NE(n.detail.find("capture time = arrival time"), std::string::npos) << n.detail;
  cam.start();
  EXPECT_EQ(cam.state(), SourceState::kStalled);  // nothing arrived yet: not streaming
  const int64_t before_ns = monotonic_now_ns();
  GstLaunch sender(testing::plain_sender_pipeline(port));
  ASSERT_TRUE(eventually([&] { return cam.stats().frames_published >= 5; }))
      << cam.stats().packets << " packets";
  EXPECT_EQ(cam.state(), SourceState::kStreaming);
  ASSERT_TRUE(cam.frames().fetch());
  const int64_t fetched_ns = monotonic_now_ns();
  const Frame& f = cam.frames().latest();
  EXPECT_EQ(f.width, 320);
  EXPECT_EQ(f.height, 240);
  EXPECT_EQ(f.stride_bytes, 320 * 4);
  EXPECT_FALSE(f.device_time_trusted);
  EXPECT_GT(f.host_timestamp_ns, before_ns);
  EXPECT_LE(f.host_timestamp_ns, fetched_ns);
  // SMPTE bars (videotestsrc's default): 7 bars across, the first white, the second yellow; in
  // RGBA videotestsrc draws them at full level (255, 255, 255) and (255, 255, 0); here they come
  // through 4:4:4 H.264 and BT.601 limited range back to RGB.
  auto px = [&](int x, int y, int c) {
    return int(f.data[std::size_t(y) * f.stride_bytes + x * 4 + c]);
  };
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(px(20, 60, c), 255, 16) << c;
  EXPECT_NEAR(px(68, 60, 0), 255, 16);
  EXPECT_NEAR(px(68, 60, 1), 255, 16);
  EXPECT_LT(px(68, 60, 2), 40);
  EXPECT_EQ(cam.stats().malformed_total, 0u);
  EXPECT_EQ(cam.stats().bus_errors, 0u);

  // The sender goes away: no frame for the stall timeout makes the camera stalled.
  sender.stop();
  EXPECT_TRUE(eventually([&] { return cam.state() == SourceState::kStalled; }));
  cam.stop();
  EXPECT_EQ(cam.state(), SourceState::kClosed);
}

TEST(RtpCamera, GarbageDatagramsAreCountedByReasonAndDroppedAndVideoStillArrives) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpCamera cam(config_for(port));
  cam.negotiate({320, 240, {}, 0.0});
  cam.start();
  constexpr int kEach = 50;
  for (int i = 0; i < kEach; ++i) {
    send_datagram(port, {0x80, 0x60, 0x00});  // too short
    std::vector<uint8_t> v1(40, 0x55);        // version 1
    send_datagram(port, v1);
    std::vector<uint8_t> csrc(20, 0);  // 15 CSRCs claimed in 20 bytes
    csrc[0] = 0x8F;
    send_datagram(port, csrc);
    std::vector<uint8_t> ext(24, 0);  // an extension of 0xFFFF words
    ext[0] = 0x90;
    ext[12] = 0xBE, ext[13] = 0xDE, ext[14] = 0xFF, ext[15] = 0xFF;
    send_datagram(port, ext);
  }
  auto count = [&](RtpPacketError e) { return cam.stats().malformed[static_cast<std::size_t>(e)]; };
  // UDP on loopback may drop under load, never add: wait for all that can still come.
  ASSERT_TRUE(eventually([&] { return cam.stats().packets >= 4u * kEach; })) << cam.stats().packets;
  EXPECT_EQ(count(RtpPacketError::kTooShort), uint64_t{kEach});
  EXPECT_EQ(count(RtpPacketError::kBadVersion), uint64_t{kEach});
  EXPECT_EQ(count(RtpPacketError::kCsrcOverrun), uint64_t{kEach});
  EXPECT_EQ(count(RtpPacketError::kExtensionOverrun), uint64_t{kEach});
  EXPECT_EQ(cam.stats().malformed_total, 4u * kEach);
  // The station's summary names them the same way (LinkReport::malformed_by_reason).
  const std::vector<std::pair<std::string, uint64_t>> expected{
      {std::string(to_string(RtpPacketError::kTooShort)), kEach},
      {std::string(to_string(RtpPacketError::kBadVersion)), kEach},
      {std::string(to_string(RtpPacketError::kCsrcOverrun)), kEach},
      {std::string(to_string(RtpPacketError::kExtensionOverrun)), kEach}};
  std::vector<std::pair<std::string, uint64_t>> reported = cam.link_report().malformed_by_reason;
  std::sort(reported.begin(), reported.end());
  std::vector<std::pair<std::string, uint64_t>> sorted = expected;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(reported, sorted);
  EXPECT_EQ(cam.stats().frames_published, 0u);
  EXPECT_NE(cam.state(), SourceState::kStreaming);

  GstLaunch sender(testing::plain_sender_pipeline(port));
  ASSERT_TRUE(eventually([&] { return cam.stats().frames_published >= 3; }));
  EXPECT_EQ(cam.stats().bus_errors, 0u);
}

TEST(RtpCamera, AFrameOfAnotherSizeIsNeverPublishedAndIsAFormatEvent) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpCamera cam(config_for(port));
  cam.negotiate({640, 480, {}, 0.0});  // calibrated at 640x480; the sender sends 320x240
  cam.start();
  GstLaunch sender(testing::plain_sender_pipeline(port));
  ASSERT_TRUE(eventually([&] { return cam.stats().wrong_format >= 3; }));
  EXPECT_EQ(cam.state(), SourceState::kFormatMismatch);
  EXPECT_EQ(cam.stats().frames_published, 0u);
  EXPECT_FALSE(cam.frames().fetch());
  FormatEvent ev;
  ASSERT_TRUE(cam.pop_format_event(ev));
  EXPECT_EQ(ev.kind, FormatEventKind::kLost);
  EXPECT_EQ(ev.expected.width_px, 640);
  EXPECT_EQ(ev.seen.width_px, 320);
  EXPECT_EQ(ev.seen.height_px, 240);
  EXPECT_FALSE(cam.pop_format_event(ev));  // one event for the run of wrong frames
}

TEST(RtpCamera, APortAlreadyTakenRefusesTheStartNamingTheAddress) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpCamera first(config_for(port));
  first.start();
  RtpCamera second(config_for(port));
  try {
    second.start();
    FAIL() << "started twice on one port";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(port)), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hd::drivers
