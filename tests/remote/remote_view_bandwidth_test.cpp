// Bandwidth follows the view (issue 12 item 5): two RtpSenders in this process (as hybrid-remote
// runs one per camera) send to two network cameras. A "not needed" message for camera 1 makes its
// sender keep only one frame in low_rate_divider, so its bytes (the station's counters) drop by
// about the divider per frame the camera produced, while camera 0 stays at full rate; "needed"
// again brings the forced key frame within a few frames and the full rate back.
//
// Windows are counted in frames the senders took, and each is used only when the sender's own
// counts show it stayed in one state throughout: the sender falls back to full rate when the
// station's feedback stops for 2 s (a loaded machine), which a window measured in time or in
// capture steps could straddle. Nothing here depends on how fast the machine is.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/sender/rtp_sender.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

constexpr int kWidth = 640, kHeight = 480;
// Frames a sender takes in one measured window (2 s at 30 Hz).
constexpr uint64_t kWindowFrames = 60;

// Frames the sender was given (sent, or skipped while not needed).
uint64_t taken(const remote::RtpSenderStats& s) {
  return s.frames_pushed + s.frames_skipped_not_needed;
}

// Both cameras' senders and stations at one moment.
struct Snapshot {
  remote::RtpSenderStats sender[2];
  RtpCameraStats camera[2];
};

// What happened between two snapshots, for camera i.
struct Window {
  uint64_t taken = 0, sent = 0, skipped = 0, forced = 0, bytes = 0, published = 0;
  bool needed_throughout = false;      // needed at both ends, nothing skipped or forced between
  bool not_needed_throughout = false;  // not needed at both ends, no key frame forced between
  double bytes_per_taken_frame() const { return taken == 0 ? 0.0 : double(bytes) / double(taken); }
};

Window window(const Snapshot& a, const Snapshot& b, int i) {
  const remote::RtpSenderStats &s0 = a.sender[i], &s1 = b.sender[i];
  Window w;
  w.taken = taken(s1) - taken(s0);
  w.sent = s1.frames_pushed - s0.frames_pushed;
  w.skipped = s1.frames_skipped_not_needed - s0.frames_skipped_not_needed;
  w.forced = s1.key_frames_forced - s0.key_frames_forced;
  w.bytes = b.camera[i].bytes - a.camera[i].bytes;
  w.published = b.camera[i].frames_published - a.camera[i].frames_published;
  // Becoming needed forces a key frame, so a window without one that is not needed at both ends
  // never was; one that is needed at both ends and skipped nothing was never not needed (the
  // first frame after "not needed" is sent, the next ones skipped: a single-frame "not needed"
  // would show as a forced key frame when it ended).
  w.needed_throughout = s0.needed && s1.needed && w.skipped == 0 && w.forced == 0;
  w.not_needed_throughout = !s0.needed && !s1.needed && w.forced == 0;
  return w;
}

// A fed sender: frames of fresh noise at 30 Hz (every frame costs x264 its whole per-frame budget,
// so bytes follow frames), as a camera produces them whatever the station says.
class Producer {
 public:
  explicit Producer(remote::RtpSender* senders[2]) {
    thread_ = std::thread([this, senders] {
      Frame f[2];
      uint64_t x = 0x9E3779B97F4A7C15ull;
      for (Frame& g : f) g.allocate_rgba(kWidth, kHeight);
      while (run_) {
        const int64_t now = monotonic_now_ns();
        for (int i = 0; i < 2; ++i) {
          for (std::size_t k = 0; k + 8 <= f[i].data.size(); k += 8) {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            std::memcpy(&f[i].data[k], &x, 8);
          }
          f[i].host_timestamp_ns = now;
          senders[i]->push(f[i]);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(33));  // the frame period
      }
    });
  }
  ~Producer() {
    run_ = false;
    thread_.join();
  }
  Producer(const Producer&) = delete;
  Producer& operator=(const Producer&) = delete;

 private:
  std::atomic<bool> run_{true};
  std::thread thread_;
};

TEST(RemoteViewBandwidth, ACameraNotNeededDropsToTheLowRateAndComesBackWithAKeyFrame) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  std::unique_ptr<RtpCamera> cams[2];
  std::unique_ptr<remote::RtpSender> senders[2];
  for (int i = 0; i < 2; ++i) {
    RtpReceiveConfig c;
    c.listen = {"127.0.0.1", static_cast<uint16_t>(port + 2 * i)};
    cams[i] = std::make_unique<RtpCamera>(c);
    cams[i]->negotiate({kWidth, kHeight, {}, 0.0});
    cams[i]->start();
  }
  // Periodic key frames 60 s (1800 frames) apart: every key frame in this test but the first is
  // forced or asked for (a PLI), and without the forcing the one after "needed" is far away.
  constexpr double kKeyIntervalS = 60.0;
  for (int i = 0; i < 2; ++i) {
    remote::RtpSendConfig c;
    c.port = static_cast<uint16_t>(port + 2 * i);
    c.width_px = kWidth;
    c.height_px = kHeight;
    c.rate_hz = 30.0;
    c.bitrate_kbps = 1000;
    c.key_interval_s = kKeyIntervalS;
    c.camera_index = static_cast<uint8_t>(i);
    senders[i] = std::make_unique<remote::RtpSender>(c);
    senders[i]->start();
  }
  remote::RtpSender* fed[2] = {senders[0].get(), senders[1].get()};
  Producer producer(fed);
  const int divider = senders[1]->config().low_rate_divider;
  ASSERT_GT(divider, 1);

  for (int i = 0; i < 2; ++i)
    ASSERT_TRUE(eventually([&] {
      return cams[i]->stats().frames_published >= 10 && cams[i]->stats().feedback_targets >= 1;
    })) << "camera "
        << i;
  for (int i = 0; i < 2; ++i) cams[i]->set_view_needed(true);

  const auto snapshot = [&] {
    Snapshot s;
    for (int i = 0; i < 2; ++i) s.sender[i] = senders[i]->stats();
    for (int i = 0; i < 2; ++i) s.camera[i] = cams[i]->stats();
    return s;
  };
  // The next window of kWindowFrames frames taken by camera 1's sender that `usable` accepts (the
  // senders' counts say they stayed in the states measured), of up to ten; the others are
  // skipped. Counted in frames, so this waits for the producer, never for the clock.
  const auto measure = [&](auto usable, Snapshot& from, Snapshot& to) {
    for (int attempt = 0; attempt < 10; ++attempt) {
      from = snapshot();
      if (!eventually(
              [&] { return taken(senders[1]->stats()) >= taken(from.sender[1]) + kWindowFrames; }))
        return false;
      to = snapshot();
      if (usable(window(from, to, 0), window(from, to, 1))) return true;
    }
    return false;
  };
  const auto both_full = [](const Window& w0, const Window& w1) {
    return w0.needed_throughout && w1.needed_throughout;
  };

  // Full rate: both cameras needed.
  Snapshot f0, f1;
  ASSERT_TRUE(measure(both_full, f0, f1)) << "no window with both cameras at full rate";
  const Window full[2] = {window(f0, f1, 0), window(f0, f1, 1)};

  // Camera 1 not needed: its sender switches once the feedback arrives.
  cams[1]->set_view_needed(false);
  ASSERT_TRUE(eventually([&] {
    const remote::RtpSenderStats s = senders[1]->stats();
    return !s.needed && s.frames_skipped_not_needed > 0;
  })) << "camera 1's sender never took 'not needed'";
  Snapshot l0, l1;
  ASSERT_TRUE(
      measure([](const Window& w0,
                 const Window& w1) { return w0.needed_throughout && w1.not_needed_throughout; },
              l0, l1))
      << "no window with camera 1 not needed throughout";
  const Window low[2] = {window(l0, l1, 0), window(l0, l1, 1)};

  const auto ratio = [](const Window& w, const Window& ref) {
    return w.bytes_per_taken_frame() / ref.bytes_per_taken_frame();
  };
  std::printf(
      "camera 1 needed: %llu frames taken, %llu sent, %llu B at the station; not needed: %llu "
      "taken, %llu sent, %llu skipped, %llu B (bytes per frame taken: ratio %.3f, divider %d); "
      "camera 0 meanwhile %llu -> %llu frames sent of %llu -> %llu taken (ratio %.3f)\n",
      static_cast<unsigned long long>(full[1].taken), static_cast<unsigned long long>(full[1].sent),
      static_cast<unsigned long long>(full[1].bytes), static_cast<unsigned long long>(low[1].taken),
      static_cast<unsigned long long>(low[1].sent), static_cast<unsigned long long>(low[1].skipped),
      static_cast<unsigned long long>(low[1].bytes), ratio(low[1], full[1]), divider,
      static_cast<unsigned long long>(full[0].sent), static_cast<unsigned long long>(low[0].sent),
      static_cast<unsigned long long>(full[0].taken), static_cast<unsigned long long>(low[0].taken),
      ratio(low[0], full[0]));
  // Not needed, the sender sends one frame in `divider` (the first of each run, then every
  // divider-th), and the station gets about 1/divider of the bytes per frame the camera made: each
  // frame sent costs what a full-rate frame costs, within a factor 2 either way (the edges of the
  // window, a key frame the station asked for).
  EXPECT_LE(low[1].sent * divider, low[1].taken + divider);
  EXPECT_GE(low[1].sent * divider + divider, low[1].taken);
  EXPECT_LT(ratio(low[1], full[1]), 2.0 / divider);
  EXPECT_GT(ratio(low[1], full[1]), 0.5 / divider);  // still sent, at the low rate
  // Camera 0 untouched: every frame sent, its bytes per frame as before.
  EXPECT_EQ(low[0].sent, low[0].taken);
  EXPECT_GT(ratio(low[0], full[0]), 0.5);
  EXPECT_LT(ratio(low[0], full[0]), 2.0);

  // Needed again: the first key frame the station decodes after the request is the forced one,
  // within a few frames (those on their way, at the low rate, while the request travelled).
  // Without the forcing the next key frame is the periodic one, over a thousand frames away:
  // the wait ends at kKeyBound frames shown without one.
  constexpr uint64_t kKeyBound = 15;
  const RtpCameraStats before = cams[1]->stats();
  const uint64_t forced_before = senders[1]->stats().key_frames_forced;
  const int64_t needed_ns = monotonic_now_ns();
  cams[1]->set_view_needed(true);
  int64_t seen_ns = 0;
  ASSERT_TRUE(eventually([&] {
    seen_ns = monotonic_now_ns();
    const RtpCameraStats s = cams[1]->stats();
    return s.key_frames > before.key_frames ||
           s.frames_published >= before.frames_published + kKeyBound;
  }));
  const RtpCameraStats at_key = cams[1]->stats();
  const uint64_t frames_between = at_key.frames_published - before.frames_published;
  std::printf(
      "needed again: %s after %.3f s, %llu frames shown before (bound %llu; periodic key frames "
      "every %.0f s); key frames forced by the sender %llu\n",
      at_key.key_frames > before.key_frames ? "a key frame" : "NO key frame",
      (seen_ns - needed_ns) * 1e-9, static_cast<unsigned long long>(frames_between),
      static_cast<unsigned long long>(kKeyBound), kKeyIntervalS,
      static_cast<unsigned long long>(senders[1]->stats().key_frames_forced - forced_before));
  EXPECT_GT(at_key.key_frames, before.key_frames)
      << frames_between << " frames shown after 'needed' and no key frame: none was forced";
  EXPECT_LT(frames_between, kKeyBound) << "the forced key frame";
  EXPECT_GE(senders[1]->stats().key_frames_forced, forced_before + 1);

  // And back at full rate: every frame sent again, bytes per frame as before "not needed".
  Snapshot b0, b1;
  ASSERT_TRUE(measure(both_full, b0, b1)) << "camera 1 never back at full rate";
  const Window back = window(b0, b1, 1);
  std::printf("back: %llu of %llu frames sent, bytes per frame taken ratio %.3f\n",
              static_cast<unsigned long long>(back.sent),
              static_cast<unsigned long long>(back.taken), ratio(back, full[1]));
  EXPECT_EQ(back.sent, back.taken);
  EXPECT_GT(ratio(back, full[1]), 0.5) << "full rate again";
  for (int i = 0; i < 2; ++i) EXPECT_GE(cams[i]->feedback().view_feedback_sent, 1u);
  EXPECT_EQ(senders[0]->stats().frames_skipped_not_needed, 0u) << "camera 0 was never lowered";
}

}  // namespace
}  // namespace hd::drivers
