// A key-frame request from the station (RtpCamera::request_key_frame → rtph264depay's upstream
// force-key-unit → rtpbin's RTCP PLI) reaches the sender's rtpbin, which turns it into a
// force-key-unit event for x264enc: the next IDR comes long before the periodic one.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/sender/rtp_sender.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

TEST(RemoteKeyFrame, APliFromTheStationMakesTheEncoderSendAnIdrBeforeItsPeriodicOne) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig rc;
  rc.listen = {"127.0.0.1", port};
  RtpCamera cam(rc);
  cam.negotiate({320, 240, {}, 0.0});
  cam.start();

  remote::RtpSendConfig sc;
  sc.port = port;
  sc.width_px = 320;
  sc.height_px = 240;
  sc.rate_hz = 30.0;
  sc.bitrate_kbps = 500;
  sc.key_interval_s = 20.0;  // periodic IDRs 600 frames apart: only the first one in this test
  remote::RtpSender sender(sc);
  sender.start();

  std::atomic<bool> run{true};
  std::thread producer;
  struct StopProducer {  // also when an assertion returns early: a joinable thread would abort
    std::atomic<bool>& run;
    std::thread& thread;
    ~StopProducer() {
      run = false;
      if (thread.joinable()) thread.join();
    }
  } stop_producer{run, producer};
  producer = std::thread([&] {  // a live camera at 30 Hz with moving content
    Frame f;
    f.allocate_rgba(sc.width_px, sc.height_px);
    for (uint8_t n = 0; run; ++n) {
      for (std::size_t i = 0; i < f.data.size(); i += 4) f.data[i] = uint8_t(i / 4 + n * 7);
      f.host_timestamp_ns = monotonic_now_ns();
      sender.push(f);
      std::this_thread::sleep_for(std::chrono::milliseconds(33));  // the frame period
    }
  });

  ASSERT_TRUE(eventually([&] { return cam.stats().frames_published >= 5; }));
  // The station's RTCP goes where the sender's comes from: it has somewhere to send a PLI once
  // the sender's first report arrived (its RTCP interval, not the video, decides when). Its PLIs
  // before then went nowhere (its depayloader asks for a key frame as the stream begins): the
  // count read while it still had no target (the target read after the count) bounds them.
  uint64_t pli_lost = 0;
  ASSERT_TRUE(eventually([&] {
    const uint64_t pli = cam.feedback().pli_sent;
    if (cam.stats().feedback_targets >= 1) return true;
    pli_lost = pli;
    return false;
  }));
  // A stretch of stream before the request long enough to show that the encoder makes no IDR of
  // its own: 60 frames (2 s), counted as the sender encodes them.
  ASSERT_TRUE(eventually([&] { return sender.stats().frames_encoded >= 60; }));
  // Exactly one key frame before the request: the stream's first. Periodic IDRs are 600 frames
  // apart, so any other was asked for, and only the station asks here: with no PLI from it since
  // it could reach the sender, the sender made exactly one IDR. On a loaded machine the station
  // may have asked on its own meanwhile (a lost packet, a stall); each such PLI adds at most one.
  // (The PLI count is read after the sender's, so a PLI behind an IDR counted is in it.)
  const remote::RtpSenderStats before = sender.stats();
  const uint64_t pli_before = cam.feedback().pli_sent;
  const uint64_t pli_reaching = pli_before - pli_lost;
  std::printf(
      "IDRs before the request: %llu sent (%llu decoded by the station); PLI from the station "
      "before it: %llu, of them %llu after it knew where the sender is\n",
      static_cast<unsigned long long>(before.key_frames),
      static_cast<unsigned long long>(cam.stats().key_frames),
      static_cast<unsigned long long>(pli_before), static_cast<unsigned long long>(pli_reaching));
  if (pli_reaching == 0) {
    EXPECT_EQ(before.key_frames, 1u) << "an IDR nobody asked for before the request";
  } else {
    EXPECT_GE(before.key_frames, 1u);
    EXPECT_LE(before.key_frames, 1 + pli_reaching) << "more IDRs than the station asked for";
  }
  ASSERT_TRUE(cam.request_key_frame());
  ASSERT_TRUE(eventually([&] { return sender.stats().key_frames > before.key_frames; }));
  const remote::RtpSenderStats after = sender.stats();
  const uint64_t frames_later = after.last_key_frame_index - (before.frames_encoded - 1);
  std::printf(
      "PLI: IDR %llu frames after the request (periodic key frame every %d frames), "
      "%llu PLI sent\n",
      static_cast<unsigned long long>(frames_later), sc.key_int_frames(),
      static_cast<unsigned long long>(cam.feedback().pli_sent));
  // The request crosses RTCP, the sender's session and its encoder's queue: a few frames. 15
  // (0.5 s at 30 Hz) bounds it on a loaded machine; the periodic IDR is 600 frames away.
  EXPECT_LE(frames_later, 15u);
  EXPECT_GE(cam.feedback().pli_sent, 1u);
  run = false;
  producer.join();
  sender.stop();
  cam.stop();
}

}  // namespace
}  // namespace hd::drivers
