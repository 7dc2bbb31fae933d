// The station's receive path under mutated packets, from a real stream: hybrid-remote's RtpSender
// encodes 45 frames (x264, every packet with its ntp-64, camera-state and sender-stages
// elements), the test records the packets off a UDP socket, then replays them renumbered (so the
// stream goes on) with mutated bytes, lengths, sequence numbers, marker bits, NAL and FU-A
// headers and extension elements:
//  - 10^6 mutated packets (in ~1.7 * 10^6) through what RtpCamera checks every packet with
//  (parse_rtp_packet,
//    check_h264_payload, read_frame_stamp) and then rtph264depay as the camera builds it
//    (depayloader_description; without check_h264_payload a 1-byte FU-A crashes it),
//    fed by an appsrc that never drops: every packet is accounted for (refused by the parser, or
//    reached the depayloader);
//  - a subset (kCameraPackets, through the decoder: decoding 10^6 packets would take minutes)
//    over UDP into a real RtpCamera (udpsrc → rtpbin → depayloader → avdec_h264 → mailbox): it
//    must count every datagram, never publish a frame older than the newest, and then show every
//    frame of a clean stream from the first key frame after its video is back.
// Run under ASan too (scripts/test.sh): no crash, no out-of-bounds read.
#include <gst/app/gstappsrc.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/gstreamer_init.h"
#include "drivers/rtp/h264_payload.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_frame_stamp.h"
#include "drivers/rtp/rtp_packet.h"
#include "drivers/rtp/rtp_receive_pipeline.h"
#include "drivers/rtp/rtp_stream_guard.h"
#include "remote/sender/rtp_sender.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

constexpr int kWidth = 320, kHeight = 240, kFrames = 45;
// Mutated packets through the checks and the depayloader (the 10^6; 60 % of the
// replay is mutated, the rest keeps frames decodable).
constexpr uint64_t kMutatedPackets = 1'000'000;
constexpr uint64_t kCameraPackets = 5'000;
// Bounds a hang only: every wait ends on its event (a datagram counted, a frame shown).
constexpr auto kHangBound = std::chrono::seconds(60);

int64_t realtime_ns() {
  timespec t{};
  ::clock_gettime(CLOCK_REALTIME, &t);
  return int64_t(t.tv_sec) * 1'000'000'000LL + t.tv_nsec;
}

// A UDP socket bound on loopback (RAII).
struct UdpSocket {
  int fd = -1;
  explicit UdpSocket(uint16_t port) {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    int size = 8 << 20;
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    timeval timeout{60, 0};  // bounds a hang only: packets are read as they come
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    if (port != 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ~UdpSocket() {
    if (fd >= 0) ::close(fd);
  }
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;
};

// The real stream: RtpSender's packets of kFrames frames of a moving picture, in order.
std::vector<std::vector<uint8_t>> record_stream() {
  const uint16_t port = testing::free_rtp_port();
  UdpSocket in(port);
  if (in.fd < 0) return {};
  remote::RtpSendConfig sc;
  sc.port = port;
  sc.width_px = kWidth;
  sc.height_px = kHeight;
  sc.rate_hz = 30.0;
  sc.bitrate_kbps = 1000;
  sc.key_interval_s = 0.5;  // IDR frames in the corpus, FU-A fragments in them
  remote::RtpSender sender(sc);
  sender.start();
  Frame f;
  f.allocate_rgba(kWidth, kHeight);
  std::vector<std::vector<uint8_t>> packets;
  // Frames are pushed until kFrames came out: x264 may hold the last few back until more come
  // (under load it held 3 of 45, and a recording that waited for them waited for its socket's
  // timeout). The bound only ends a sender that stopped.
  std::atomic<int> frames{0};
  std::thread feeder([&] {
    for (int n = 0; frames.load() < kFrames && n < 20 * kFrames; ++n) {
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          uint8_t* p = f.data.data() + std::size_t(y) * f.stride_bytes + std::size_t(x) * 4;
          p[0] = uint8_t(x + 4 * n);
          p[1] = uint8_t(y * 2 + x * n);
          p[2] = uint8_t((x * y) >> 4);
          p[3] = 255;
        }
      f.host_timestamp_ns = monotonic_now_ns();
      sender.push(f);
      std::this_thread::sleep_for(std::chrono::milliseconds(33));  // the frame rate
    }
  });
  std::vector<uint8_t> buf(65536);
  while (frames.load() < kFrames) {
    const ssize_t n = ::recv(in.fd, buf.data(), buf.size(), 0);
    if (n <= 0) break;
    packets.emplace_back(buf.begin(), buf.begin() + n);
    if (n >= 2 && (buf[1] & 0x80)) ++frames;  // the marker ends a frame
  }
  feeder.join();
  sender.stop();
  return packets;
}

// Replays the corpus as one endless stream with mutations.
class Mutator {
 public:
  explicit Mutator(const std::vector<std::vector<uint8_t>>& corpus, uint64_t seed)
      : corpus_(corpus), rng_(seed), t0_ns_(monotonic_now_ns()) {}
  uint64_t mutated() const { return mutated_; }
  /// The packet next() returned last is a frame's first (its corpus RTP time is new).
  bool began_frame() const { return began_frame_; }

  // The next packet: renumbered (sequence, RTP time, and a fresh ntp-64 capture time, as a
  // live sender's), then with `mutate` percent probability mutated 1..3 ways. A live sender's
  // RTP time follows its clock: each frame's (the corpus packets of one RTP time) is the 90 kHz
  // time since the replay began when its first packet leaves, however fast the replay goes (a
  // replay faster than its own RTP times would be a sender whose clock races, which
  // rtpjitterbuffer answers by holding packets up to a second: not what this fuzz is about).
  const std::vector<uint8_t>& next(int mutate_percent) {
    const std::size_t k = index_ % corpus_.size();
    ++index_;
    p_ = corpus_[k];
    const uint16_t seq = uint16_t(sequence_++);
    p_[2] = uint8_t(seq >> 8);
    p_[3] = uint8_t(seq);
    const uint32_t corpus_ts =
        (uint32_t{p_[4]} << 24) | (uint32_t{p_[5]} << 16) | (uint32_t{p_[6]} << 8) | p_[7];
    began_frame_ = index_ == 1 || corpus_ts != corpus_ts_;
    if (began_frame_) {  // a new frame
      corpus_ts_ = corpus_ts;
      const auto clock_ts = uint32_t((monotonic_now_ns() - t0_ns_) * 9 / 100'000);
      ts_ = std::max(clock_ts, ts_ + 1);
    }
    for (int i = 0; i < 4; ++i) p_[4 + i] = uint8_t(ts_ >> (24 - 8 * i));
    RtpPacketView v;
    std::span<const uint8_t> ntp;
    if (parse_rtp_packet(p_, v) == RtpPacketError::kNone &&
        find_rtp_extension(v, kNtp64ExtensionId, ntp) && ntp.size() == 8) {
      const uint64_t t = unix_ns_to_ntp64(realtime_ns() - 5'000'000);
      uint8_t* at = p_.data() + (ntp.data() - p_.data());
      for (int i = 0; i < 8; ++i) at[i] = uint8_t(t >> (56 - 8 * i));
    }
    if (int(rng_() % 100) >= mutate_percent) return p_;
    ++mutated_;
    const int ways = 1 + int(rng_() % 3);
    for (int w = 0; w < ways; ++w) mutate_once();
    return p_;
  }

 private:
  std::size_t payload_offset() const {
    RtpPacketView v;
    if (parse_rtp_packet(p_, v) != RtpPacketError::kNone || v.payload.empty()) return 0;
    return std::size_t(v.payload.data() - p_.data());
  }
  void mutate_once() {
    const std::size_t size = p_.size();
    switch (rng_() % 10) {
      case 0:  // flip 1..4 bytes anywhere
        for (int i = 0, n = 1 + int(rng_() % 4); i < n && size > 0; ++i)
          p_[rng_() % size] ^= uint8_t(1 + rng_() % 255);
        break;
      case 1:  // truncate
        p_.resize(rng_() % (size + 1));
        break;
      case 2: {  // append garbage
        const int n = 1 + int(rng_() % 64);
        for (int i = 0; i < n; ++i) p_.push_back(uint8_t(rng_()));
        break;
      }
      case 3:  // a sequence number from anywhere
        if (size >= 4) {
          p_[2] = uint8_t(rng_());
          p_[3] = uint8_t(rng_());
        }
        break;
      case 4:  // marker bit toggled
        if (size >= 2) p_[1] ^= 0x80;
        break;
      case 5: {  // a FU-A with random start/end bits and NAL type
        const std::size_t at = payload_offset();
        if (at != 0 && at + 1 < p_.size()) {
          p_[at] = uint8_t((p_[at] & 0xE0) | 28);
          p_[at + 1] = uint8_t(rng_());
        }
        break;
      }
      case 6: {  // any NAL unit type (STAP, MTAP, reserved ...)
        const std::size_t at = payload_offset();
        if (at != 0 && at < p_.size()) p_[at] = uint8_t((p_[at] & 0xE0) | (rng_() % 32));
        break;
      }
      case 7:  // the extension block's bytes (element headers and values)
        if (size > 16) p_[16 + rng_() % std::min<std::size_t>(size - 16, 40)] = uint8_t(rng_());
        break;
      case 8:  // version, padding, extension and CSRC-count bits
        if (size >= 1) p_[0] = uint8_t(rng_());
        break;
      case 9:  // header only, or a payload of one byte
        p_.resize(std::min(size, payload_offset() + (rng_() % 2)));
        break;
    }
  }

  const std::vector<std::vector<uint8_t>>& corpus_;
  std::mt19937_64 rng_;
  std::vector<uint8_t> p_;
  uint64_t index_ = 0, mutated_ = 0;
  uint32_t sequence_ = 1000;
  int64_t t0_ns_;
  uint32_t corpus_ts_ = 0, ts_ = 0;  // the current frame's RTP time in the corpus and as sent
  bool began_frame_ = false;
};

// A packet of an IDR access unit as x264 and rtph264pay send it (an access unit delimiter, then
// SPS, PPS and the IDR slices): SPS, PPS or an IDR slice, alone, first in a STAP-A, or a fragment
// of an IDR slice (FU-A).
bool carries_key_frame(std::span<const uint8_t> packet) {
  RtpPacketView v;
  if (parse_rtp_packet(packet, v) != RtpPacketError::kNone || v.payload.empty()) return false;
  const auto key_nal = [](uint8_t type) { return type == 5 || type == 7 || type == 8; };
  const uint8_t type = v.payload[0] & 0x1F;
  if (type == 24) return v.payload.size() > 3 && key_nal(v.payload[3] & 0x1F);  // STAP-A
  if (type == 28) return v.payload.size() > 1 && (v.payload[1] & 0x1F) == 5;    // FU-A
  return key_nal(type);
}

class DepayloadFuzz : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ensure_gstreamer();
    corpus_ = new std::vector<std::vector<uint8_t>>(record_stream());
  }
  static void TearDownTestSuite() { delete corpus_; }
  static std::vector<std::vector<uint8_t>>* corpus_;
};
std::vector<std::vector<uint8_t>>* DepayloadFuzz::corpus_ = nullptr;

TEST_F(DepayloadFuzz, AMillionMutatedPacketsThroughTheChecksAndTheDepayloaderAreAllAccountedFor) {
  ASSERT_GE(corpus_->size(), std::size_t(kFrames));
  GError* error = nullptr;
  const std::string d =
      "appsrc name=src is-live=false block=true max-bytes=262144 format=time "
      "caps=\"application/x-rtp,media=video,clock-rate=90000,encoding-name=H264,payload=96\" ! " +
      depayloader_description() + " ! fakesink name=sink sync=false async=false";
  GstElement* pipeline = gst_parse_launch(d.c_str(), &error);
  ASSERT_NE(pipeline, nullptr);
  ASSERT_EQ(error, nullptr) << error->message;
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
  GstElement* depay = gst_bin_get_by_name(GST_BIN(pipeline), rtp_elements::kDepayloader);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  std::atomic<uint64_t> into_depay{0}, access_units{0};
  auto count = [](GstPad*, GstPadProbeInfo*, gpointer n) {
    static_cast<std::atomic<uint64_t>*>(n)->fetch_add(1);
    return GST_PAD_PROBE_OK;
  };
  GstPad* in = gst_element_get_static_pad(depay, "sink");
  GstPad* out = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(in, GST_PAD_PROBE_TYPE_BUFFER, count, &into_depay, nullptr);
  gst_pad_add_probe(out, GST_PAD_PROBE_TYPE_BUFFER, count, &access_units, nullptr);
  gst_object_unref(in);
  gst_object_unref(out);
  ASSERT_NE(gst_element_set_state(pipeline, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);

  const auto t0 = std::chrono::steady_clock::now();
  Mutator m(*corpus_, 20261202);
  uint64_t refused = 0, accepted = 0, stamps = 0, stamp_errors = 0;
  uint64_t packets = 0;
  for (uint64_t i = 0; m.mutated() < kMutatedPackets; ++i, ++packets) {
    const std::vector<uint8_t>& p = m.next(60);
    RtpPacketView v;
    if (parse_rtp_packet(p, v) != RtpPacketError::kNone ||
        check_h264_payload(v.payload) != RtpPacketError::kNone) {  // what RtpCamera drops
      ++refused;
      continue;
    }
    RtpFrameStamp s;
    if (v.has_extension) (read_frame_stamp(v, s) == StampError::kNone ? stamps : stamp_errors)++;
    ++accepted;
    GstBuffer* b = gst_buffer_new_memdup(p.data(), p.size());
    GST_BUFFER_PTS(b) = i * GST_MSECOND;
    ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), b), GST_FLOW_OK) << "packet " << i;
  }
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  GstBus* bus = gst_element_get_bus(pipeline);
  GstMessage* msg = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  ASSERT_NE(msg, nullptr);
  EXPECT_EQ(GST_MESSAGE_TYPE(msg), GST_MESSAGE_EOS);
  gst_message_unref(msg);
  gst_object_unref(bus);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "%llu packets (%llu mutated) in %.1f s: %llu refused by the parser, %llu to the "
      "depayloader (%llu with a stamp, %llu stamps refused), %llu access units out\n",
      static_cast<unsigned long long>(packets), static_cast<unsigned long long>(m.mutated()),
      seconds, static_cast<unsigned long long>(refused), static_cast<unsigned long long>(accepted),
      static_cast<unsigned long long>(stamps), static_cast<unsigned long long>(stamp_errors),
      static_cast<unsigned long long>(access_units.load()));
  EXPECT_EQ(refused + accepted, packets);
  EXPECT_GE(m.mutated(), kMutatedPackets);
  EXPECT_EQ(into_depay.load(), accepted);  // every accepted packet reached the depayloader
  EXPECT_GT(refused, 0u);
  EXPECT_GT(stamp_errors, 0u);
  EXPECT_GT(access_units.load(), 0u);  // the clean packets still make frames
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(src);
  gst_object_unref(depay);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
}

// Before RtpStreamGuard the camera's udpsrc thread stopped here after a few hundred mutated
// datagrams (rtpjitterbuffer's retransmission timers for wild sequence gaps, docs/network.md).
// Every wait is for an event (the camera counted the datagrams, a frame was shown), bounded by
// kHangBound only.
TEST_F(DepayloadFuzz, MutatedPacketsIntoTheCameraAreCountedNoOldFrameIsShownAndVideoComesBack) {
  ASSERT_GE(corpus_->size(), std::size_t(kFrames));
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig rc;
  rc.listen = {"127.0.0.1", port};
  RtpCamera cam(rc);
  cam.negotiate({kWidth, kHeight, {}, 0.0});
  cam.start();
  UdpSocket out(0);
  ASSERT_GE(out.fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  to.sin_port = htons(port);

  // What the render loop sees, polling the mailbox.
  uint64_t shown = 0, older_than_shown = 0;
  int64_t newest_ns = 0;
  // The clean stream's return (its first packet's capture time), and when and with which
  // capture time the first frame captured since was shown.
  int64_t back_ns = std::numeric_limits<int64_t>::max(), video_again_ns = 0, first_back_ns = 0;
  uint64_t shown_clean = 0, frames_sent = 0;  // frames of the clean stream shown / sent
  auto poll = [&] {
    if (!cam.frames().fetch()) return;
    const int64_t t = cam.frames().latest().host_timestamp_ns;
    const int64_t now = monotonic_now_ns();
    if (t <= newest_ns || t > now) ++older_than_shown;
    newest_ns = std::max(newest_ns, t);
    ++shown;
    if (t >= back_ns) ++shown_clean;
    if (video_again_ns == 0 && t >= back_ns) {
      video_again_ns = now;
      first_back_ns = t;
    }
  };
  uint64_t sent = 0, send_failed = 0;
  // The camera's stats along the path, for a wait that ends on its bound.
  auto path = [&] {
    const RtpCameraStats d = cam.stats();
    char line[512];
    std::snprintf(
        line, sizeof line,
        "%llu datagrams sent, %llu counted, %llu passed on, %llu depayloaded, %llu "
        "access units, %llu decoded, %llu converted, %llu published (%llu shown), %llu "
        "not newer, %llu lost in the jitter buffer, %llu too late, camera %s",
        static_cast<unsigned long long>(sent), static_cast<unsigned long long>(d.packets),
        static_cast<unsigned long long>(d.accepted),
        static_cast<unsigned long long>(d.packets_depayloaded),
        static_cast<unsigned long long>(d.access_units),
        static_cast<unsigned long long>(d.frames_decoded),
        static_cast<unsigned long long>(d.frames_converted),
        static_cast<unsigned long long>(d.frames_published), static_cast<unsigned long long>(shown),
        static_cast<unsigned long long>(d.not_newer),
        static_cast<unsigned long long>(d.jitter_lost),
        static_cast<unsigned long long>(d.jitter_too_late), to_string(cam.state()).data());
    return std::string(line);
  };
  // Polls until `done` or kHangBound (a hang, not a measurement); false on the bound, with a
  // failure that says what was waited for and where the path stands.
  auto poll_until = [&](const char* what, auto done) {
    const auto bound = std::chrono::steady_clock::now() + kHangBound;
    while (!done()) {
      if (std::chrono::steady_clock::now() >= bound) {
        ADD_FAILURE() << "waited " << kHangBound.count() << " s for " << what << ": " << path();
        return false;
      }
      poll();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return true;
  };
  Mutator m(*corpus_, 7);
  bool counted = true;  // every batch was counted before the next was sent
  // Sends n packets of the replay, in batches the socket buffer holds: each batch once the
  // camera has counted the one before. `frame_period`: a live sender's pace (0: as fast as the
  // camera counts).
  auto send = [&](uint64_t n, int mutate_percent, std::chrono::milliseconds frame_period) {
    auto next_frame = std::chrono::steady_clock::now();
    for (uint64_t i = 0; i < n && counted; ++i) {
      const std::vector<uint8_t>& p = m.next(mutate_percent);
      if (p.empty()) continue;  // udpsrc skips an empty datagram itself: nothing to count
      const bool frame_end = p.size() >= 2 && (p[1] & 0x80) != 0;
      if (::sendto(out.fd, p.data(), p.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to) <
          0) {
        ++send_failed;
        continue;
      }
      ++sent;
      if (frame_end) ++frames_sent;
      if (sent % 16 == 0)
        counted = poll_until("the camera to count every datagram",
                             [&] { return cam.stats().packets >= sent; });
      if (frame_end && frame_period.count() > 0) {
        next_frame += frame_period;
        while (std::chrono::steady_clock::now() < next_frame) {  // the sender's frame clock
          poll();
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
      }
    }
    counted = counted && poll_until("the camera to count every datagram",
                                    [&] { return cam.stats().packets >= sent; });
  };
  send(kCameraPackets, 60, std::chrono::milliseconds(0));
  ASSERT_TRUE(counted) << "the camera stopped counting datagrams: " << cam.stats().packets << " of "
                       << sent;
  poll();
  const uint64_t shown_in_fuzz = shown;
  const uint64_t requests_before = cam.feedback().key_frame_requests;
  const SourceState state_after_fuzz = cam.state();
  const RtpCameraStats after_fuzz = cam.stats();
  // Then the clean stream, three passes of the corpus (its key frames every 0.5 s), as a live
  // sender sends it: its packets carry capture times from now on (the replay stamps each packet 5
  // ms before it leaves, as a live sender's encoder would), and each frame leaves at least a frame
  // period (33 ms) after the last packet of the one before. It begins wherever the fuzz left the
  // corpus, mid-frame or among frames predicted from ones the fuzz mangled, and behind the fuzz's
  // packets still in the jitter buffer and the decoder's queue (the fuzz goes as fast as udpsrc
  // counts, faster than they drain): those can push the first clean frames past the jitter
  // buffer's 20 ms latency, and such a loss costs the frames up to the next key frame. Once video
  // is back (a clean frame shown: the path is through the backlog) and the clean stream has gone
  // past every sequence number a fuzzed packet can hold in the jitter buffer (up to
  // kMaxSequenceJump ahead of the stream, RtpStreamGuard: such a stray is kept and the clean
  // packet of its number dropped as a duplicate; measured once in about a hundred runs, the first
  // clean key frame broken so), every frame from the next whole key frame on must be shown. Each
  // one is waited for (the mailbox shows it) before the next leaves, so a loaded machine slows the
  // stream down instead of making the jitter buffer or the queue drop a frame: one that never shows
  // is one the fuzz broke the path for (before the jitter buffer's fix, df6041f, only the key
  // frames were shown).
  back_ns = monotonic_now_ns() - 5'000'000;
  frames_sent = 0;
  const uint64_t sent_in_fuzz = sent;
  constexpr auto kFramePeriod = std::chrono::milliseconds(33);
  constexpr int kPasses = 3;
  uint64_t frames_from_key = 0, shown_from_key = 0;  // frames from that key frame on
  uint64_t frames_to_key = 0;                        // clean frames sent before it
  int64_t first_key_ns = 0;  // a capture time between that key frame's and the one before
  int64_t frame_ns = 0;      // likewise for the frame being sent
  bool frame_whole = false, frame_key = false;  // the frame being sent began here / is a key frame
  bool from_key = false, all_shown = true;
  for (uint64_t i = 0; i < kPasses * corpus_->size() && counted && all_shown; ++i) {
    const int64_t before_ns = monotonic_now_ns();
    const std::vector<uint8_t>& p = m.next(0);
    if (m.began_frame()) {
      // Its packets are stamped from before_ns - 5 ms on; the frame before's ended at least a
      // frame period earlier, stamped 5 ms before it left.
      frame_ns = before_ns - 5'000'000 - kFramePeriod.count() * 1'000'000 / 2;
      frame_whole = true;
      frame_key = false;
    }
    frame_key = frame_key || carries_key_frame(p);
    if (::sendto(out.fd, p.data(), p.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to) < 0) {
      ++send_failed;
      continue;
    }
    ++sent;
    if (p.size() < 2 || (p[1] & 0x80) == 0) continue;  // the marker ends a frame
    ++frames_sent;
    counted = poll_until("the camera to count every datagram",
                         [&] { return cam.stats().packets >= sent; });
    if (!from_key && frame_whole && frame_key && video_again_ns != 0 &&
        sent - sent_in_fuzz > uint64_t(RtpStreamGuard::kMaxSequenceJump)) {
      from_key = true;
      first_key_ns = frame_ns;
      frames_to_key = frames_sent - 1;
    }
    if (from_key) {
      ++frames_from_key;
      all_shown = poll_until("a clean frame to be shown", [&] { return newest_ns >= frame_ns; });
      if (all_shown) ++shown_from_key;
    }
    const auto next_frame = std::chrono::steady_clock::now() + kFramePeriod;
    while (std::chrono::steady_clock::now() < next_frame) {  // the sender's frame period
      poll();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  counted = counted && poll_until("the camera to count every datagram",
                                  [&] { return cam.stats().packets >= sent; });
  const bool video_again = video_again_ns != 0;
  // -1: no video again (printed as such; asserted below).
  const double to_video_s = video_again ? (video_again_ns - back_ns) * 1e-9 : -1.0;
  const double first_capture_s = video_again ? (first_back_ns - back_ns) * 1e-9 : -1.0;
  EXPECT_TRUE(counted) << "the camera stopped counting datagrams";
  const RtpCameraStats s = cam.stats();
  const RtpCamera::Feedback fb = cam.feedback();
  auto reason = [&](RtpPacketError e) {
    return static_cast<unsigned long long>(s.malformed[static_cast<std::size_t>(e)]);
  };
  std::printf(
      "%llu datagrams sent (%llu mutated), %llu received: %llu malformed (%llu sequence jumps, "
      "%llu RTP time jumps, %llu other SSRC), %llu to GStreamer, %llu renumberings taken; "
      "%llu frames published, %llu shown during the fuzz, %llu not newer dropped, %llu of "
      "another size, %llu key frames decoded, %llu bus errors, %llu older shown as new\n",
      static_cast<unsigned long long>(sent), static_cast<unsigned long long>(m.mutated()),
      static_cast<unsigned long long>(s.packets),
      static_cast<unsigned long long>(s.malformed_total), reason(RtpPacketError::kSequenceJump),
      reason(RtpPacketError::kRtpTimeJump), reason(RtpPacketError::kOtherSsrc),
      static_cast<unsigned long long>(s.accepted),
      static_cast<unsigned long long>(s.sequence_resyncs),
      static_cast<unsigned long long>(s.frames_published),
      static_cast<unsigned long long>(shown_in_fuzz), static_cast<unsigned long long>(s.not_newer),
      static_cast<unsigned long long>(s.wrong_format),
      static_cast<unsigned long long>(s.key_frames), static_cast<unsigned long long>(s.bus_errors),
      static_cast<unsigned long long>(older_than_shown));
  std::printf(
      "clean stream back: video again %.3f s later, the frame shown captured %.3f s after the "
      "clean stream began (key frame every 0.5 s; camera %s after the fuzz, %llu key-frame "
      "requests then, %llu after; %llu PLI); %llu of its %llu frames shown, %llu of the %llu "
      "from the first key frame after that on (clean frame %llu, %.3f s in)\n",
      to_video_s, first_capture_s, to_string(state_after_fuzz).data(),
      static_cast<unsigned long long>(requests_before),
      static_cast<unsigned long long>(fb.key_frame_requests),
      static_cast<unsigned long long>(fb.pli_sent), static_cast<unsigned long long>(shown_clean),
      static_cast<unsigned long long>(frames_sent), static_cast<unsigned long long>(shown_from_key),
      static_cast<unsigned long long>(frames_from_key),
      static_cast<unsigned long long>(frames_to_key + 1),
      from_key ? (first_key_ns - back_ns) * 1e-9 : -1.0);
  const auto since_fuzz = [&](uint64_t RtpCameraStats::*c) {
    return static_cast<unsigned long long>(s.*c - after_fuzz.*c);
  };
  std::printf(
      "clean stream: %llu of its datagrams refused; since the fuzz the jitter buffer dropped %llu "
      "too late and %llu over its latency, the kernel %lld (in all), %llu packets depayloaded, "
      "%llu frames decoded, %llu converted, %llu not newer, %llu damaged, %llu without verdict, "
      "%llu of another size, "
      "%llu not fitting their calibration, %llu published\n",
      since_fuzz(&RtpCameraStats::malformed_total), since_fuzz(&RtpCameraStats::jitter_too_late),
      since_fuzz(&RtpCameraStats::jitter_over_latency), static_cast<long long>(s.kernel_drops),
      since_fuzz(&RtpCameraStats::packets_depayloaded), since_fuzz(&RtpCameraStats::frames_decoded),
      since_fuzz(&RtpCameraStats::frames_converted), since_fuzz(&RtpCameraStats::not_newer),
      since_fuzz(&RtpCameraStats::frames_damaged),
      since_fuzz(&RtpCameraStats::frames_without_verdict),
      since_fuzz(&RtpCameraStats::wrong_format),
      since_fuzz(&RtpCameraStats::calibration_size_mismatch),
      since_fuzz(&RtpCameraStats::frames_published));
  // Every datagram is counted and accounted for (refused by reason, or passed on).
  EXPECT_EQ(s.accepted + s.malformed_total, s.packets);
  EXPECT_EQ(s.packets, sent);
  EXPECT_EQ(send_failed, 0u);
  EXPECT_GT(s.malformed_total, 0u);
  EXPECT_GT(reason(RtpPacketError::kSequenceJump), 0u);  // the mutator's wild sequence numbers
  EXPECT_EQ(older_than_shown, 0u);                       // never an older frame presented as new
  // Video came back, and from the next key frame on the whole clean stream was shown, frame by
  // frame: at least two key-frame intervals (30 frames), a key frame and every frame predicted
  // from it.
  EXPECT_TRUE(video_again) << "no video after the fuzz";
  ASSERT_TRUE(from_key) << "no whole key frame in the clean stream after video came back";
  EXPECT_GE(frames_from_key, 30u);
  EXPECT_EQ(shown_from_key, frames_from_key)
      << "frame " << shown_from_key + 1 << " from the key frame (clean frame "
      << frames_to_key + shown_from_key + 1 << ") was never shown";
  EXPECT_EQ(cam.state(), SourceState::kStreaming);
  cam.stop();
}

}  // namespace
}  // namespace hd::drivers
