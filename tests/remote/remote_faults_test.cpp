// Faults in the receive path (GStreamer netsim before rtpbin; netem is not available here), with
// hybrid-remote --scene scenes/default.yaml as the sender: for 0 / 1 / 5 % loss x 0 / 20 / 50 ms
// jitter the camera shows video and never presents an older frame as new, and after a 3 s cut
// video is back within 1 s of the link's return. Prints the faults table (docs/network.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::string> remote_to(uint16_t port) {
  return {hd::test::remote_bin(), "--scene",
          std::string(hd::test::source_dir()) + "/scenes/default.yaml", "--to",
          "rtp://127.0.0.1:" + std::to_string(port)};
}

// What a consumer (the render loop) sees while polling the mailbox each millisecond.
struct Watch {
  uint64_t shown = 0;
  uint64_t older_than_shown = 0;  ///< frames presented as new that were not newer: must be 0
  int64_t newest_ns = 0;
  void poll(RtpCamera& cam) {
    if (!cam.frames().fetch()) return;
    const int64_t t = cam.frames().latest().host_timestamp_ns;
    if (t <= newest_ns || t > monotonic_now_ns()) ++older_than_shown;
    newest_ns = std::max(newest_ns, t);
    ++shown;
  }
};

TEST(RemoteFaults, LossAndJitterTableNeverPresentsOldVideoAsNew) {
  constexpr double kSeconds = 2.0;  // of streaming per cell, after the first frame
  // Where the frames went: decoded and published by the camera, shown (polled); and what the
  // receive path dropped: datagrams by the kernel (the socket's buffer full), packets by the
  // jitter buffer (late / over its latency). Counted over the whole cell, its start included.
  std::printf(
      "| loss | jitter ms | RTX | frames shown | frames lost (of %g s x 30 Hz) | old shown as new "
      "| NACK sent | retransmissions received | decoded | published | kernel drops | jitter "
      "buffer drops late / over latency |\n",
      kSeconds);
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  uint64_t shown_5_percent[2] = {0, 0};  // frames shown at 5 % loss over the jitter cells: off, on
  for (double loss : {0.0, 0.01, 0.05})
    for (int jitter_ms : {0, 20, 50}) {
      uint64_t shown_without_rtx = 0;
      for (bool rtx : {false, true}) {
        const uint16_t port = testing::free_rtp_port();
        ASSERT_NE(port, 0);
        RtpReceiveConfig c;
        c.listen = {"127.0.0.1", port};
        c.retransmission = rtx;  // off: no NACK, no RTX receiver (the sender's RTX stays idle)
        c.netsim_always = true;
        c.netsim_drop_probability = loss;
        c.netsim_max_delay_ms = jitter_ms;
        RtpCamera cam(c);
        cam.negotiate({640, 480, {}, 0.0});
        cam.start();
        testing::ChildProcess remote(remote_to(port));
        Watch w;
        ASSERT_TRUE(eventually([&] {
          w.poll(cam);
          return w.shown > 0;
        })) << loss
            << " " << jitter_ms << " rtx " << rtx;
        const auto end = Clock::now() + std::chrono::duration<double>(kSeconds);
        while (Clock::now() < end) {
          w.poll(cam);
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        const double expected = kSeconds * 30.0;
        const RtpCamera::Feedback fb = cam.feedback();
        const RtpCameraStats st = cam.stats();
        std::printf(
            "| %.0f %% | 0..%d | %s | %llu | %.0f | %llu | %llu | %llu | %llu | %llu | %lld | %llu "
            "/ %llu |\n",
            loss * 100, jitter_ms, rtx ? "on" : "off", static_cast<unsigned long long>(w.shown),
            std::max(0.0, expected - double(w.shown)),
            static_cast<unsigned long long>(w.older_than_shown),
            static_cast<unsigned long long>(fb.nack_sent),
            static_cast<unsigned long long>(fb.rtx_received),
            static_cast<unsigned long long>(st.frames_decoded),
            static_cast<unsigned long long>(st.frames_published),
            static_cast<long long>(st.kernel_drops),
            static_cast<unsigned long long>(st.jitter_too_late),
            static_cast<unsigned long long>(st.jitter_over_latency));
        // How many frames a cell shows depends on the machine's load as much as on the faults
        // (the table reports it); that video is shown at all is asserted by the wait above.
        EXPECT_EQ(w.older_than_shown, 0u) << loss << " " << jitter_ms << " rtx " << rtx;
        EXPECT_EQ(st.capture_after_arrival, 0u) << loss << " " << jitter_ms;
        EXPECT_GE(st.kernel_drops, 0) << "the socket's drops were not measured";
        if (!rtx) {
          shown_without_rtx = w.shown;
          EXPECT_EQ(fb.rtx_received, 0u);
          continue;
        }
        // Lost packets were asked for again and came back (RFC 4588 over rtpbin's aux elements).
        // Waited for, not counted in the window: under saturation (stress-ng 4 on 2 cores beside
        // ASan) a 1 % cell once ended its window with one NACK sent and nothing back yet.
        if (loss > 0.0) {
          EXPECT_TRUE(eventually([&] {
            w.poll(cam);
            return cam.feedback().rtx_received > 0;
          })) << loss
              << " " << jitter_ms;
          EXPECT_EQ(w.older_than_shown, 0u) << loss << " " << jitter_ms << " after the wait";
        }
        if (loss >= 0.05) {
          shown_5_percent[0] += shown_without_rtx;
          shown_5_percent[1] += w.shown;
        }
      }
    }
  // Frames shown with and without RTX are printed, not asserted: on an idle machine (load 0.6,
  // 08:28 UTC 2026-12-02) RTX showed more at 1 % loss (150 against 133 over the jitter cells)
  // but not at 5 % (71 against 75), where a lost last packet of a frame (noticed only with the
  // next frame, past the 20 ms jitter buffer) still costs the frames up to the next key frame.
  std::printf("frames shown at 5 %% loss over the jitter cells: RTX off %llu, on %llu\n",
              static_cast<unsigned long long>(shown_5_percent[0]),
              static_cast<unsigned long long>(shown_5_percent[1]));
}

TEST(RemoteFaults, AfterAThreeSecondCutVideoIsBackWithinOneSecond) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", port};
  c.netsim_always = true;
  RtpCamera cam(c);
  cam.negotiate({640, 480, {}, 0.0});
  cam.start();
  testing::ChildProcess remote(remote_to(port));
  Watch w;
  ASSERT_TRUE(eventually([&] {
    w.poll(cam);
    return w.shown >= 10;
  }));
  const auto cut = Clock::now();
  ASSERT_TRUE(cam.set_netsim_drop_probability(1.0));
  ASSERT_TRUE(eventually([&] { return cam.state() == SourceState::kStalled; }));
  w.poll(cam);  // what was in flight at the cut
  const uint64_t before = w.shown;
  std::this_thread::sleep_until(cut + std::chrono::seconds(3));  // the cut's length, not a sync
  w.poll(cam);
  EXPECT_EQ(w.shown, before) << "video shown while the link was cut";
  EXPECT_EQ(cam.state(), SourceState::kStalled);
  const int64_t back_ns = monotonic_now_ns();
  ASSERT_TRUE(cam.set_netsim_drop_probability(0.0));
  ASSERT_TRUE(eventually([&] {
    w.poll(cam);
    return w.shown > before && w.newest_ns > back_ns;
  }));
  const double to_video_s = (monotonic_now_ns() - back_ns) * 1e-9;
  // The first frame shown after the return was captured this long after it: the link's own
  // recovery (key frame request, next key frame), free of how slowly a loaded machine decodes.
  const double first_capture_s = (w.newest_ns - back_ns) * 1e-9;
  const RtpCamera::Feedback fb = cam.feedback();
  std::printf(
      "3 s cut: video again %.3f s after the link's return (the frame shown was captured %.3f s "
      "after it; key frame every 0.5 s; %llu key-frame requests, %llu PLI, %llu NACK sent)\n",
      to_video_s, first_capture_s, static_cast<unsigned long long>(fb.key_frame_requests),
      static_cast<unsigned long long>(fb.pli_sent), static_cast<unsigned long long>(fb.nack_sent));
  EXPECT_LT(first_capture_s, 1.0);
  EXPECT_GE(fb.key_frame_requests, 1u);  // packets came back to a stalled camera: it asked
  EXPECT_GE(fb.pli_sent, 1u);            // and rtpbin sent the request as an RTCP PLI
  EXPECT_EQ(w.older_than_shown, 0u);
  EXPECT_EQ(cam.state(), SourceState::kStreaming);
}

TEST(RemoteFaults, ASenderKilledAndRestartedIsShownAgainAndNothingOldIsShown) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", port};
  RtpCamera cam(c);
  cam.negotiate({640, 480, {}, 0.0});
  cam.start();
  Watch w;
  {
    testing::ChildProcess remote(remote_to(port));
    ASSERT_TRUE(eventually([&] {
      w.poll(cam);
      return w.shown >= 10;
    }));
  }  // killed (SIGKILL): no BYE
  ASSERT_TRUE(eventually([&] { return cam.state() == SourceState::kStalled; }));
  w.poll(cam);
  const uint64_t before = w.shown;
  const int64_t restarted_ns = monotonic_now_ns();
  testing::ChildProcess again(remote_to(port));  // a new process: a new SSRC, new RTP times
  ASSERT_TRUE(eventually([&] {
    w.poll(cam);
    return w.shown > before && w.newest_ns > restarted_ns;
  })) << cam.stats().bus_errors
      << " bus errors, last: " << cam.stats().last_error;
  std::printf("sender restarted: video again %.3f s later (%llu pipeline rebuilds)\n",
              (monotonic_now_ns() - restarted_ns) * 1e-9,
              static_cast<unsigned long long>(cam.stats().restarts));
  EXPECT_EQ(w.older_than_shown, 0u);
}

}  // namespace
}  // namespace hd::drivers
