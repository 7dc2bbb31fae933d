// Faults in the receive path (GStreamer netsim before rtpbin; netem is not available here), with
// hybrid-remote --scene scenes/default.yaml as the sender: for 0 / 1 / 5 % loss x 0 / 20 / 50 ms
// jitter, with repair off, RTX and RTX + FEC, the share of frames shown is asserted and no older
// frame is ever presented as new; after a 3 s cut video is back within 1 s of the link's return; a
// killed and restarted sender is shown again. Prints the faults table (docs/network.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/mailbox_watch.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::string> remote_to(uint16_t port, int fec_percent = 0) {
  return {hd::test::remote_bin(),
          "--scene",
          std::string(hd::test::source_dir()) + "/scenes/default.yaml",
          "--to",
          "rtp://127.0.0.1:" + std::to_string(port),
          "--fec",
          std::to_string(fec_percent)};
}

using Watch = testing::MailboxWatch;

// How a cell repairs loss: not at all (no NACK, no RTX), with NACK and RTX (the station's and
// hybrid-remote's defaults), with ULP FEC on top (hybrid-remote --fec kFecPercent), or with FEC
// alone (the station asks for nothing).
enum class Repair { kOff, kRtx, kRtxFec, kFec };
constexpr int kFecPercent = 20;

const char* name(Repair r) {
  switch (r) {
    case Repair::kOff:
      return "off";
    case Repair::kRtx:
      return "RTX";
    case Repair::kRtxFec:
      return "RTX + FEC 20 %";
    case Repair::kFec:
      return "FEC 20 %";
  }
  return "?";
}

// One cell of the faults table: what reached this host, what was shown, what it cost.
struct Cell {
  double loss = 0.0;
  int jitter_ms = 0;
  Repair repair = Repair::kOff;
  uint64_t arrived = 0, published = 0, shown = 0, older_than_shown = 0;
  RtpCameraStats stats;
  RtpCamera::Feedback feedback;
  double latency_p50_ms = 0.0;  ///< capture to published (the sender's stamp, same host)
  double kbytes_per_s = 0.0;    ///< received on the RTP port, retransmissions included
  double share() const { return arrived == 0 ? 0.0 : double(published) / double(arrived); }
};

// Streams hybrid-remote's camera 0 through netsim and counts, over kFrames frames after a
// warm-up of kWarmUpFrames, the frames that reached this host (at the socket, before netsim) and
// those of them that were shown (published: by their arrival time, so no frame in flight at the
// window's start is counted on one side only). Counted by events, so a loaded machine runs the
// same cell, only slower. The warm-up is the stream's start (rtpbin builds its stream while the
// first packets wait, and the jitter budget measures the link for 1 s); its frames are not in the
// shares. Then the sender is killed and the camera drains until it stalls.
Cell run_cell(double loss, int jitter_ms, Repair repair) {
  constexpr uint64_t kWarmUpFrames = 30;
  constexpr uint64_t kFrames = 150;  // 5 s at 30 Hz: 1 % of it is 1.5 frames
  Cell cell;
  cell.loss = loss;
  cell.jitter_ms = jitter_ms;
  cell.repair = repair;
  const uint16_t port = testing::free_rtp_port();
  EXPECT_NE(port, 0);
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", port};
  // Off: no NACK, no RTX receiver, no frame-end requests (the sender's RTX stays idle); the
  // jitter buffer is sized from the link either way.
  c.retransmission = repair == Repair::kRtx || repair == Repair::kRtxFec;
  c.netsim_always = true;
  c.netsim_drop_probability = loss;
  c.netsim_max_delay_ms = jitter_ms;
  RtpCamera cam(c);
  cam.negotiate({640, 480, {}, 0.0});
  cam.start();
  Watch w;
  std::vector<double> latencies_ms;
  int64_t window_ns = INT64_MAX;  // frames that arrived from then on are counted
  uint64_t shown_in_window = 0;
  auto drain_timings = [&] {
    RtpFrameTiming t;
    while (cam.pop_timing(t)) {
      if (t.arrival_ns < window_ns) continue;
      ++shown_in_window;
      if (t.stamped) latencies_ms.push_back(double(t.published_ns - t.capture_ns) * 1e-6);
    }
  };
  uint64_t arrived_before = 0, bytes_before = 0;
  int64_t last_ns = 0;
  {
    testing::ChildProcess remote(
        remote_to(port, repair == Repair::kRtxFec || repair == Repair::kFec ? kFecPercent : 0));
    EXPECT_TRUE(eventually([&] {
      w.poll(cam);
      drain_timings();
      return cam.stats().frames_arrived >= kWarmUpFrames;
    })) << loss
        << " " << jitter_ms << " repair " << name(repair);
    const RtpCameraStats before = cam.stats();
    arrived_before = before.frames_arrived;
    bytes_before = before.bytes;
    window_ns = monotonic_now_ns();
    EXPECT_TRUE(eventually([&] {
      w.poll(cam);
      drain_timings();
      return cam.stats().frames_arrived >= arrived_before + kFrames;
    })) << loss
        << " " << jitter_ms << " repair " << name(repair);
    last_ns = monotonic_now_ns();
    cell.kbytes_per_s = double(cam.stats().bytes - bytes_before) / 1e3 /
                        std::max(1e-3, double(last_ns - window_ns) * 1e-9);
  }  // killed
  EXPECT_TRUE(eventually([&] {
    w.poll(cam);
    drain_timings();
    return cam.state() == SourceState::kStalled;
  }));
  drain_timings();
  cell.stats = cam.stats();
  cell.arrived = cell.stats.frames_arrived - arrived_before;
  cell.published = shown_in_window;
  cell.shown = w.shown;
  cell.older_than_shown = w.older_than_shown;
  cell.feedback = cam.feedback();
  if (!latencies_ms.empty()) {
    std::nth_element(latencies_ms.begin(), latencies_ms.begin() + latencies_ms.size() / 2,
                     latencies_ms.end());
    cell.latency_p50_ms = latencies_ms[latencies_ms.size() / 2];
  }
  return cell;
}

// The faults table: loss 0 / 1 / 5 % x jitter 0 / 20 / 50 ms x repair off / RTX / RTX + FEC
// (RTX: the station's defaults, NACK and RTX, frame-end requests, the jitter buffer sized from the
// link; FEC: hybrid-remote --fec 20 on top). Asserted on the share of the frames that reached
// this host which were shown (published):
// - at 0 % loss every frame (the sender may be killed inside its last frame's burst: 1 frame);
// - at 1 % loss with repair at least 95 %, at 5 % at least 80 %; with RTX alone only with 0 or
//   20 ms of jitter (see below); with loss, 10 (1 %) or 15 (5 %) points more than without repair.
// Never an old frame as new. Counted by frames, not time, so a loaded machine runs the same cells.
TEST(RemoteFaults, LossAndJitterTableShowsTheFramesItPromisesAndNeverOldAsNew) {
  std::printf(
      "| loss | jitter ms | repair | frames shown / reached the host | share | latency p50 ms "
      "(capture to shown) | jitter buffer ms (transit spread of originals, of repairs) | kB/s | "
      "NACK sent | frame-end requests | retransmissions received | rebuilt from FEC | kernel "
      "drops | jitter buffer drops late / over latency / declared lost | frames out of the "
      "depayloader / decoded / key frames / not newer | old shown as new |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  // HD_FAULTS_CELL="LOSS_PERCENT,JITTER_MS" runs that cell only (to look into one).
  const char* only = std::getenv("HD_FAULTS_CELL");
  for (double loss : {0.0, 0.01, 0.05})
    for (int jitter_ms : {0, 20, 50}) {
      if (only != nullptr &&
          std::string(only) != std::to_string(int(loss * 100)) + "," + std::to_string(jitter_ms))
        continue;
      double share_without = 0.0;
      for (Repair repair : {Repair::kOff, Repair::kRtx, Repair::kRtxFec}) {
        const Cell cell = run_cell(loss, jitter_ms, repair);
        const RtpCameraStats& st = cell.stats;
        std::printf(
            "| %.0f %% | 0..%d | %s | %llu / %llu | %.1f %% | %.1f | %d (%.1f, %.1f) | %.0f | %llu "
            "| %llu | %llu | %llu | %lld | %llu / %llu / %llu | %llu / %llu / %llu / %llu | %llu "
            "|\n",
            loss * 100, jitter_ms, name(repair), static_cast<unsigned long long>(cell.published),
            static_cast<unsigned long long>(cell.arrived), cell.share() * 100, cell.latency_p50_ms,
            st.jitter_buffer_latency_ms, st.transit_spread_ms, st.repair_spread_ms,
            cell.kbytes_per_s, static_cast<unsigned long long>(cell.feedback.nack_sent),
            static_cast<unsigned long long>(st.frame_end_requests),
            static_cast<unsigned long long>(cell.feedback.rtx_received),
            static_cast<unsigned long long>(st.fec_recovered),
            static_cast<long long>(st.kernel_drops),
            static_cast<unsigned long long>(st.jitter_too_late),
            static_cast<unsigned long long>(st.jitter_over_latency),
            static_cast<unsigned long long>(st.jitter_lost),
            static_cast<unsigned long long>(st.access_units),
            static_cast<unsigned long long>(st.frames_decoded),
            static_cast<unsigned long long>(st.key_frames),
            static_cast<unsigned long long>(st.not_newer),
            static_cast<unsigned long long>(cell.older_than_shown));
        std::fflush(stdout);
        const std::string where = std::to_string(int(loss * 100)) + " % loss, 0.." +
                                  std::to_string(jitter_ms) + " ms, repair " + name(repair);
        EXPECT_EQ(cell.older_than_shown, 0u) << where;
        EXPECT_EQ(st.capture_after_arrival, 0u)
            << where << " (" << st.access_units_retimed
            << " access units retimed past the previous one's PTS)";
        EXPECT_GE(st.kernel_drops, 0) << "the socket's drops were not measured: " << where;
        EXPECT_GT(cell.arrived, 0u) << where;
        if (loss == 0.0) {
          EXPECT_GE(cell.published + 1, cell.arrived) << where;
        }
        if (repair == Repair::kOff) {
          share_without = cell.share();
          EXPECT_EQ(cell.feedback.rtx_received, 0u) << where;
          continue;
        }
        // No FEC where none was sent (the FEC decoder may still rebuild a packet the jitter
        // buffer gave up on from a late copy in its storage: counted in fec_recovered).
        if (repair == Repair::kRtx) {
          EXPECT_EQ(st.fec_packets, 0u) << where;
        }
        // With RTX alone, at 50 ms of jitter the shares are not held reliably: a retransmission
        // waits ~50 ms in netsim's queue like any packet, and some repairs come after their
        // deadline (measured under stress-ng --cpu 2: 93.3 % at 1 %, 79.3-85.3 % at 5 %, 4-14
        // packets given up per cell). Asserted there: clearly more than no repair. FEC, which
        // needs no round trip, holds them.
        const bool held = repair == Repair::kRtxFec || jitter_ms < 50;
        if (held && loss == 0.01) {
          EXPECT_GE(cell.share(), 0.95) << where;
        }
        if (held && loss == 0.05) {
          EXPECT_GE(cell.share(), 0.80) << where;
        }
        if (loss > 0.0) {
          EXPECT_GT(cell.share(), share_without + (loss == 0.01 ? 0.10 : 0.15)) << where;
        }
      }
    }
}

// FEC on its own, with no NACK: the packets the jitter buffer gives up on are rebuilt from their
// frame's FEC packets (20 % more packets; rtpulpfecdec recovers one loss per FEC packet's set),
// so clearly more frames are shown than without, at no round trip.
TEST(RemoteFaults, FecAloneRebuildsLostPacketsWithoutAskingForThem) {
  const Cell off = run_cell(0.05, 0, Repair::kOff);
  const Cell fec = run_cell(0.05, 0, Repair::kFec);
  std::printf(
      "5 %% loss: %.1f %% shown without repair, %.1f %% with FEC alone (%llu packets "
      "rebuilt, %llu given up on, %.0f against %.0f kB/s)\n",
      off.share() * 100, fec.share() * 100,
      static_cast<unsigned long long>(fec.stats.fec_recovered),
      static_cast<unsigned long long>(fec.stats.jitter_lost), fec.kbytes_per_s, off.kbytes_per_s);
  EXPECT_EQ(fec.feedback.nack_sent, 0u);
  EXPECT_EQ(fec.feedback.rtx_received, 0u);
  // ~12 packets a frame at 5 %: ~90 lost in 150 frames, most alone in their FEC set.
  EXPECT_GE(fec.stats.fec_recovered, 20u);
  EXPECT_GT(fec.share(), off.share() + 0.10);
  // What it costs: FEC packets, about 20 % more (counted, as bytes per second follow the load).
  EXPECT_EQ(off.stats.fec_packets, 0u);
  EXPECT_GT(fec.stats.fec_packets, fec.stats.packets / 10);
  EXPECT_EQ(fec.older_than_shown, 0u);
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
