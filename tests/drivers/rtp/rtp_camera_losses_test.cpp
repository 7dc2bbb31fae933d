// Where the network camera's receive path can lose what arrived, against real sockets: the RTP
// socket's kernel buffer after start (forced above net.core.rmem_max as root), every datagram
// counted as received or as dropped by the kernel, and the jitter buffer's drops counted.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <fstream>
#include <vector>

#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

RtpReceiveConfig config_for(uint16_t port) {
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", port};
  return c;
}

void send_datagram(int socket, uint16_t port, const std::vector<uint8_t>& bytes) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::sendto(socket, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
}

// CAP_NET_ADMIN (bit 12) in this process's effective set: what SO_RCVBUFFORCE needs.
bool has_net_admin() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("CapEff:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> 12) & 1;
  return false;
}

TEST(RtpCameraSocket, AfterStartTheRtpSocketHoldsTheAskedBufferAsRootAlsoAboveRmemMax) {
  if (::geteuid() != 0)
    GTEST_SKIP() << "not root: without privilege the kernel caps a socket's buffer at "
                    "net.core.rmem_max; run as root (CI does) to check that udpsrc forces it";
  if (!has_net_admin())
    GTEST_SKIP() << "root without CAP_NET_ADMIN (a restricted container): SO_RCVBUFFORCE is "
                    "refused here";
  const int64_t rmem_max = read_rmem_max();
  ASSERT_GT(rmem_max, 0);
  std::vector<int64_t> asks{RtpReceiveConfig{}.receive_buffer_bytes};
  // Above the limit the plain SO_RCVBUF is capped: only udpsrc's SO_RCVBUFFORCE gets it.
  if (rmem_max < INT_MAX / 2) asks.push_back(rmem_max + 1024 * 1024);
  for (const int64_t asked : asks) {
    const uint16_t port = testing::free_rtp_port();
    ASSERT_NE(port, 0);
    RtpReceiveConfig c = config_for(port);
    c.receive_buffer_bytes = static_cast<int>(asked);
    RtpCamera cam(c);
    // The start report's figure, probed as udpsrc sets it before the pipeline's socket exists.
    const FormatNegotiation n = cam.negotiate({320, 240, {}, 0.0});
    EXPECT_NE(n.detail.find("RTP receive buffer asked " + std::to_string(asked) + " B, got "),
              std::string::npos)
        << n.detail;
    EXPECT_EQ(n.detail.find("LESS than asked"), std::string::npos) << n.detail;
    cam.start();
    const RtpCameraStats s = cam.stats();  // udpsrc's own sockets, read back
    EXPECT_EQ(s.rtp_buffer.asked_bytes, asked);
    EXPECT_GE(s.rtp_buffer.got_bytes, asked) << "rmem_max " << rmem_max;
    EXPECT_EQ(s.rtp_buffer.rmem_max_bytes, rmem_max);
    EXPECT_GE(s.rtcp_buffer.got_bytes, c.rtcp_receive_buffer_bytes);
    EXPECT_EQ(s.kernel_drops, 0);  // measured, and nothing was sent to the port
    std::printf("asked %lld B, udpsrc's socket has %lld B (net.core.rmem_max %lld B)\n",
                static_cast<long long>(asked), static_cast<long long>(s.rtp_buffer.got_bytes),
                static_cast<long long>(rmem_max));
  }
}

// A buffer of a few datagrams and a burst far beyond it: how many the kernel drops depends on
// how fast udpsrc's thread reads (the machine's load), but every datagram is either received or
// counted as dropped on that socket.
TEST(RtpCameraSocket, EveryDatagramIsCountedAsReceivedOrAsDroppedByTheKernel) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig c = config_for(port);
  c.receive_buffer_bytes = 4096;
  RtpCamera cam(c);
  cam.negotiate({320, 240, {}, 0.0});
  cam.start();
  ASSERT_EQ(cam.stats().kernel_drops, 0);
  const int tx = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  constexpr uint64_t kSent = 400;
  const std::vector<uint8_t> garbage(1200, 0x55);  // version 1: refused by the camera's parser
  for (uint64_t i = 0; i < kSent; ++i) send_datagram(tx, port, garbage);
  ::close(tx);
  RtpCameraStats s;
  ASSERT_TRUE(eventually([&] {
    s = cam.stats();
    return s.kernel_drops >= 0 && s.packets + uint64_t(s.kernel_drops) == kSent;
  })) << s.packets
      << " received, " << s.kernel_drops << " dropped by the kernel";
  EXPECT_EQ(s.malformed_total, s.packets);
  std::printf("%llu datagrams: %llu received, %lld dropped by the kernel (buffer %lld B)\n",
              static_cast<unsigned long long>(kSent), static_cast<unsigned long long>(s.packets),
              static_cast<long long>(s.kernel_drops),
              static_cast<long long>(s.rtp_buffer.got_bytes));
}

// An RTP packet of payload type 96 carrying one non-IDR slice NAL unit (junk after its header).
std::vector<uint8_t> rtp_packet(uint16_t seq) {
  const uint32_t ts = 90000, ssrc = 0x1234abcd;
  std::vector<uint8_t> p{0x80,
                         96,
                         uint8_t(seq >> 8),
                         uint8_t(seq),
                         uint8_t(ts >> 24),
                         uint8_t(ts >> 16),
                         uint8_t(ts >> 8),
                         uint8_t(ts),
                         uint8_t(ssrc >> 24),
                         uint8_t(ssrc >> 16),
                         uint8_t(ssrc >> 8),
                         uint8_t(ssrc),
                         0x41};
  p.resize(p.size() + 100, 0x9a);
  return p;
}

TEST(RtpCameraJitterBuffer, APacketOlderThanOnesItPassedOnIsDroppedAndCountedAsTooLate) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpCamera cam(config_for(port));
  cam.negotiate({320, 240, {}, 0.0});
  cam.start();
  const int tx = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  for (uint16_t seq = 1000; seq < 1010; ++seq) send_datagram(tx, port, rtp_packet(seq));
  // All ten through the jitter buffer (the first after its 20 ms latency, the rest in order).
  ASSERT_TRUE(eventually([&] { return cam.stats().packets_depayloaded >= 10; }))
      << cam.stats().packets << " received, " << cam.stats().packets_depayloaded << " out";
  EXPECT_EQ(cam.stats().jitter_too_late, 0u);
  send_datagram(tx, port, rtp_packet(1005));  // again, after 1009 left the jitter buffer
  ::close(tx);
  ASSERT_TRUE(eventually([&] { return cam.stats().jitter_too_late >= 1; }))
      << cam.stats().packets << " received, " << cam.stats().malformed_total << " refused";
  const RtpCameraStats s = cam.stats();
  EXPECT_EQ(s.jitter_too_late, 1u);
  EXPECT_EQ(s.jitter_over_latency, 0u);
  EXPECT_EQ(s.packets_depayloaded, 10u);  // the late one never reached the depayloader
  EXPECT_EQ(s.malformed_total, 0u);
}

}  // namespace
}  // namespace hd::drivers
