// The receive path's buffers and kernel drops without a camera: the pipeline asks udpsrc for the
// configured buffers and decodes behind a queue, the report names the sysctl when the kernel gave
// less, and the drops read from /proc/net/udp are the datagrams an unread socket could not hold.
#include "drivers/rtp/rtp_receive_socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <vector>

#include "drivers/rtp/rtp_receive_pipeline.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

// The udpsrc element named `name` in a description: its text up to the next link or element.
std::string element_text(const std::string& description, const std::string& name) {
  const std::size_t at = description.find("udpsrc name=" + name + " ");
  if (at == std::string::npos) return "";
  const std::size_t end = std::min(description.find(" ! ", at), description.find(" udpsrc ", at));
  return description.substr(at, end == std::string::npos ? std::string::npos : end - at);
}

TEST(RtpReceiveSocket, ThePipelineAsksBothUdpsrcsForTheirConfiguredBuffers) {
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", 5600};
  c.receive_buffer_bytes = 3'000'000;
  c.rtcp_receive_buffer_bytes = 100'000;
  for (bool srtp : {false, true}) {
    if (srtp) c.srtp_key = SrtpKey{};
    const std::string d = receive_pipeline_description(c);
    const std::string rtp = element_text(d, rtp_elements::kRtpSource);
    const std::string rtcp = element_text(d, rtp_elements::kRtcpSource);
    EXPECT_NE(rtp.find(" buffer-size=3000000"), std::string::npos) << d;
    EXPECT_NE(rtcp.find(" buffer-size=100000"), std::string::npos) << d;
  }
  // 0: the system's default, so udpsrc is not asked at all.
  c.receive_buffer_bytes = 0;
  c.rtcp_receive_buffer_bytes = 0;
  EXPECT_EQ(receive_pipeline_description(c).find("buffer-size"), std::string::npos);
  // The defaults ask for a buffer: 2 MiB for the stream (see RtpReceiveConfig).
  const RtpReceiveConfig defaults;
  EXPECT_EQ(defaults.receive_buffer_bytes, 2 * 1024 * 1024);
  EXPECT_GT(defaults.rtcp_receive_buffer_bytes, 0);
}

// The jitter buffer's thread only hands packets to the queue; depayloading, decoding and the
// conversion run on the queue's thread, which may wait for a CPU up to decode_queue_ms behind.
TEST(RtpReceiveSocket, TheDecoderRunsBehindAQueueSoTheJitterBufferNeverWaitsForIt) {
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", 5600};
  c.decode_queue_ms = 300;
  const std::string d = receive_pipeline_description(c);
  EXPECT_NE(d.find(std::string("rtpbin. ! queue name=") + rtp_elements::kDecodeQueue +
                   " max-size-buffers=0 max-size-bytes=0 max-size-time=300000000 ! " +
                   depayloader_description() + " ! "),
            std::string::npos)
      << d;
  EXPECT_EQ(RtpReceiveConfig{}.decode_queue_ms, 500);
}

TEST(SocketBufferText, SaysAskedGotAndTheLimitAndNamesTheSysctlOnlyWhenItGotLess) {
  const std::string enough = socket_buffer_text({2'097'152, 2'097'152, 4'194'304});
  EXPECT_EQ(enough, "asked 2097152 B, got 2097152 B (net.core.rmem_max 4194304 B)");
  const std::string more = socket_buffer_text({2'097'152, 3'000'000, 212'992});  // forced
  EXPECT_EQ(more.find("sysctl"), std::string::npos) << more;
  const std::string less = socket_buffer_text({2'097'152, 212'992, 212'992});
  EXPECT_EQ(less.rfind("asked 2097152 B, got 212992 B (net.core.rmem_max 212992 B): LESS", 0), 0u)
      << less;
  EXPECT_NE(less.find("sysctl -w net.core.rmem_max=2097152"), std::string::npos) << less;
  EXPECT_NE(less.find("root"), std::string::npos) << less;
  EXPECT_NE(socket_buffer_text({2'097'152, -1, 212'992}).find("not measured"), std::string::npos);
  EXPECT_NE(socket_buffer_text({0, 212'992, 212'992}).find("default"), std::string::npos);
}

TEST(UdpDrops, TheDropsColumnOfTheLineWithTheSocketsInodeIsRead) {
  const std::string text =
      "   sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid  "
      "timeout inode ref pointer drops\n"
      "  117: 0100007F:15E0 00000000:0000 07 00000000:00000000 00:00000000 00000000     0        "
      "0 4242 2 0000000000000000 0\n"
      "  118: 0100007F:15E1 00000000:0000 07 00000000:00004800 00:00000000 00000000     0        "
      "0 4243 2 0000000000000000 57\n";
  EXPECT_EQ(udp_drops_in(text, 4242), std::optional<uint64_t>(0));
  EXPECT_EQ(udp_drops_in(text, 4243), std::optional<uint64_t>(57));
  EXPECT_FALSE(udp_drops_in(text, 99));
  EXPECT_FALSE(udp_drops_in("", 4242));
}

// Nothing reads the socket while the datagrams come, so what its smallest buffer cannot hold is
// dropped; every datagram is either still queued or counted by the kernel.
TEST(UdpDrops, AnUnreadSocketsDropsAreTheDatagramsItsBufferCouldNotHold) {
  const int rx = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(rx, 0);
  const int smallest = 1;  // the kernel raises it to its minimum
  ASSERT_EQ(::setsockopt(rx, SOL_SOCKET, SO_RCVBUF, &smallest, sizeof smallest), 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  ASSERT_EQ(::bind(rx, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(::getsockname(rx, reinterpret_cast<sockaddr*>(&a), &len), 0);
  EXPECT_EQ(udp_socket_drops(rx), std::optional<uint64_t>(0));
  const int tx = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  constexpr int kSent = 50;
  const std::vector<uint8_t> datagram(1000, 0x55);
  for (int i = 0; i < kSent; ++i)
    ASSERT_EQ(::sendto(tx, datagram.data(), datagram.size(), 0, reinterpret_cast<sockaddr*>(&a),
                       sizeof a),
              ssize_t(datagram.size()));
  ::close(tx);
  ::fcntl(rx, F_SETFL, O_NONBLOCK);
  uint64_t received = 0;
  std::optional<uint64_t> drops;
  // Loopback delivers within sendto, or soon after from the kernel's softirq thread.
  ASSERT_TRUE(eventually([&] {
    std::vector<uint8_t> in(2000);
    while (::recv(rx, in.data(), in.size(), 0) > 0) ++received;
    drops = udp_socket_drops(rx);
    return drops && received + *drops == uint64_t{kSent};
  })) << received
      << " received, " << drops.value_or(0) << " dropped";
  EXPECT_GT(*drops, 0u);  // a buffer of ~2 KB never holds 50 KB
  ::close(rx);
}

TEST(SocketBufferProbe, ReportsTheLimitAndAtLeastTheDefaultAndNothingAskedIsTheDefault) {
  const int64_t rmem_max = read_rmem_max();
  ASSERT_GT(rmem_max, 0);
  const SocketBuffer b = probe_socket_buffer(rmem_max / 2);  // within the limit: granted as is
  EXPECT_EQ(b.rmem_max_bytes, rmem_max);
  EXPECT_GE(b.got_bytes, rmem_max / 2);
  EXPECT_FALSE(b.short_of_asked());
  const SocketBuffer d = probe_socket_buffer(0);
  EXPECT_EQ(d.asked_bytes, 0);
  EXPECT_GT(d.got_bytes, 0);
}

}  // namespace
}  // namespace hd::drivers
