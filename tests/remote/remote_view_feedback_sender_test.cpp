// The sender's side of bandwidth follows the view, fed by a plain UDP socket: malformed view
// feedback is counted by reason and ignored (full rate), "not needed" lowers the rate, and when
// the station falls silent the camera is sent at full rate again with a key frame.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/view_feedback.h"
#include "remote/sender/rtp_sender.h"
#include "test_wait.h"

namespace hd::remote {
namespace {

class Udp {  // one datagram socket, closed on destruction
 public:
  Udp() : fd_(::socket(AF_INET, SOCK_DGRAM, 0)) {}
  ~Udp() {
    if (fd_ >= 0) ::close(fd_);
  }
  Udp(const Udp&) = delete;
  Udp& operator=(const Udp&) = delete;
  void send(uint16_t port, std::span<const uint8_t> bytes) const {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
  }

 private:
  int fd_;
};

std::vector<uint8_t> message(bool needed, uint16_t sequence) {
  std::array<uint8_t, drivers::kViewFeedbackSize> b{};
  drivers::write_view_feedback({0, needed, sequence}, b);
  return {b.begin(), b.end()};
}

// A small sender fed at 30 Hz by a producer thread, as hybrid-remote feeds one; nobody listens
// to its stream (the sender only is under test).
class FedSender {
 public:
  // `adjust` sets what the test is about on a small 160x120 stream's config.
  template <class F>
  explicit FedSender(F adjust) : sender_(small_config(adjust)) {
    sender_.start();
    producer_ = std::thread([this] {
      drivers::Frame f;
      f.allocate_rgba(sender_.config().width_px, sender_.config().height_px);
      while (run_) {
        f.host_timestamp_ns = drivers::monotonic_now_ns();
        sender_.push(f);
        std::this_thread::sleep_for(std::chrono::milliseconds(33));  // the frame period
      }
    });
  }
  ~FedSender() {
    run_ = false;
    producer_.join();
    sender_.stop();
  }
  FedSender(const FedSender&) = delete;
  FedSender& operator=(const FedSender&) = delete;
  RtpSender& operator*() { return sender_; }
  RtpSender* operator->() { return &sender_; }

 private:
  template <class F>
  static RtpSendConfig small_config(F adjust) {
    RtpSendConfig c;
    c.port = drivers::testing::free_rtp_port();
    c.width_px = 160;
    c.height_px = 120;
    c.bitrate_kbps = 200;
    adjust(c);
    return c;
  }
  RtpSender sender_;
  std::atomic<bool> run_{true};
  std::thread producer_;
};

// Two refused messages are counted by their reasons and change nothing: a few frames later the
// camera is still sent at full rate and no feedback was taken.
void expect_refused_at_full_rate(RtpSender& sender, drivers::ViewFeedbackError first,
                                 drivers::ViewFeedbackError second) {
  ASSERT_TRUE(eventually([&] {
    const RtpSenderStats s = sender.stats();
    return s.view_feedback_malformed[size_t(first)] == 1 &&
           s.view_feedback_malformed[size_t(second)] == 1;
  }));
  const uint64_t pushed = sender.stats().frames_pushed;
  ASSERT_TRUE(eventually([&] { return sender.stats().frames_pushed >= pushed + 3; }));
  EXPECT_TRUE(sender.stats().needed);  // still full rate
  EXPECT_EQ(sender.stats().frames_skipped_not_needed, 0u);
  EXPECT_EQ(sender.stats().view_feedback_received, 0u);
}

TEST(RemoteViewFeedbackSender, MalformedIsCountedAndIgnoredAndSilenceMeansFullRate) {
  FedSender fed([](RtpSendConfig& c) {
    c.key_interval_s = 20.0;  // the only IDRs: the first and the forced one
    c.view_feedback_timeout_s = 0.5;
  });
  RtpSender& sender = *fed;
  ASSERT_NE(sender.config().port, 0);
  ASSERT_NE(sender.rtcp_port(), 0);
  ASSERT_TRUE(eventually([&] { return sender.stats().key_frames >= 1; }));

  Udp udp;
  std::vector<uint8_t> bad_version = message(false, 1);
  bad_version[12] = 9;
  std::vector<uint8_t> bad_length = message(false, 2);
  bad_length.push_back(0);
  udp.send(sender.rtcp_port(), bad_version);
  udp.send(sender.rtcp_port(), bad_length);
  using E = drivers::ViewFeedbackError;
  ASSERT_NO_FATAL_FAILURE(expect_refused_at_full_rate(sender, E::kBadVersion, E::kBadLength));

  // "Not needed", repeated as a station does: frames are skipped.
  uint16_t seq = 10;
  ASSERT_TRUE(eventually([&] {
    udp.send(sender.rtcp_port(), message(false, seq++));
    return sender.stats().frames_skipped_not_needed >= 10;
  }));
  EXPECT_FALSE(sender.stats().needed);
  EXPECT_EQ(sender.stats().key_frames_forced, 0u);
  // Silence: after view_feedback_timeout_s the camera is needed again, with a key frame.
  ASSERT_TRUE(eventually([&] { return sender.stats().needed; }));
  ASSERT_TRUE(eventually([&] { return sender.stats().key_frames >= 2; }));
  EXPECT_EQ(sender.stats().key_frames_forced, 1u);
}

// With a key, nobody without it can lower a camera: untagged feedback and feedback tagged with
// another key are counted by reason and change nothing; the station's own (tagged) is taken.
TEST(RemoteViewFeedbackSender, WithAKeyOnlyFeedbackTaggedWithThatKeyIsTaken) {
  drivers::SrtpKey key, other;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) {
    key.bytes[i] = uint8_t(0x40 + i);
    other.bytes[i] = uint8_t(0x41 + i);
  }
  FedSender fed([&](RtpSendConfig& c) { c.srtp_key = key; });
  RtpSender& sender = *fed;
  ASSERT_NE(sender.config().port, 0);
  ASSERT_NE(sender.rtcp_port(), 0);
  ASSERT_TRUE(eventually([&] { return sender.stats().frames_pushed >= 1; }));

  Udp udp;
  std::array<uint8_t, drivers::kAuthenticatedViewFeedbackSize> forged{};
  drivers::write_view_feedback({0, false, 1}, drivers::view_feedback_key(other), forged);
  udp.send(sender.rtcp_port(), message(false, 2));
  udp.send(sender.rtcp_port(), forged);
  using E = drivers::ViewFeedbackError;
  ASSERT_NO_FATAL_FAILURE(expect_refused_at_full_rate(sender, E::kNotAuthenticated, E::kBadTag));

  const drivers::ViewFeedbackKey mine = drivers::view_feedback_key(key);
  uint16_t seq = 10;
  ASSERT_TRUE(eventually([&] {
    std::array<uint8_t, drivers::kAuthenticatedViewFeedbackSize> b{};
    drivers::write_view_feedback({0, false, seq++}, mine, b);
    udp.send(sender.rtcp_port(), b);
    return sender.stats().frames_skipped_not_needed >= 5;
  }));
  EXPECT_FALSE(sender.stats().needed);
  EXPECT_GE(sender.stats().view_feedback_received, 1u);
}

}  // namespace
}  // namespace hd::remote
