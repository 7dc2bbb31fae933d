// hybrid-remote --intra-refresh into the station's RtpCamera through netsim loss, retransmission
// off: the stream heals by refresh sweeps, not key frames (no IDR after the first unless the
// station asks), a decoded frame is shown only once whole (damaged ones counted, never shown),
// and nothing old is shown as new. A PLI gets no IDR either. DISABLED_Measure prints shares and
// bytes against the default (IDR every 0.5 s + PLI).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/mailbox_watch.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

constexpr double kRateHz = 30.0;    // scenes/default.yaml's cameras
constexpr int kRefreshFrames = 15;  // hybrid-remote's default --key-interval-s 0.5 at 30 Hz

std::vector<std::string> remote_to(uint16_t port, bool intra_refresh) {
  std::vector<std::string> a{hd::test::remote_bin(),
                             "--scene",
                             std::string(hd::test::source_dir()) + "/scenes/default.yaml",
                             "--to",
                             "rtp://127.0.0.1:" + std::to_string(port),
                             "--no-rtx"};
  if (intra_refresh) a.push_back("--intra-refresh");
  return a;
}

using Watch = testing::MailboxWatch;

RtpReceiveConfig camera_config(uint16_t port, double loss) {
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", port};
  c.retransmission = false;  // no repair to hide a loss
  c.netsim_always = true;
  c.netsim_drop_probability = loss;
  return c;
}

// Every frame into the appsink is accounted for: shown, damaged, or refused for another counted
// reason (the last one may still be on its way); and none more than access units out of the
// depayloader (damaged ones may end there, or in the decoder, which outputs nothing for some).
void expect_accounted(const RtpCameraStats& s) {
  const uint64_t refused =
      s.frames_damaged + s.not_newer + s.wrong_format + s.calibration_size_mismatch;
  EXPECT_LE(s.frames_published + refused, s.access_units);
  EXPECT_GE(s.frames_published + refused + 1, s.frames_converted);
}

// One loss, made by cutting the link for a few packets: the frames come back whole within two
// sweeps with no key frame and no PLI. A PLI sent anyway gets no IDR either: x264enc answers a
// force-key-unit with intra refresh on by starting a sweep (gstx264enc.c).
TEST(RemoteIntraRefresh, ALossHealsWithinTwoSweepsWithoutAKeyFrameOrPliAndAPliGetsNoIdr) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpCamera cam(camera_config(port, 0.0));
  cam.negotiate({640, 480, {}, 0.0});
  cam.start();
  testing::ChildProcess remote(remote_to(port, true));
  Watch w;
  // Whole frames, and one sweep's recovery point seen (the station then knows the sender heals
  // by refresh).
  ASSERT_TRUE(eventually([&] {
    w.poll(cam);
    return w.shown >= 10 && cam.stats().heals_by_refresh;
  }));
  RtpCameraStats before = cam.stats();
  EXPECT_EQ(before.refresh_frames, kRefreshFrames);
  EXPECT_EQ(before.key_frames, 1u) << "an IDR after the first, nobody asked";
  const RtpCamera::Feedback fb_before = cam.feedback();
  const int64_t last_whole_ns = w.newest_ns;
  ASSERT_TRUE(cam.set_netsim_drop_probability(1.0));
  ASSERT_TRUE(eventually([&] { return cam.stats().packets >= before.packets + 3; }));
  ASSERT_TRUE(cam.set_netsim_drop_probability(0.0));
  ASSERT_TRUE(eventually([&] { return cam.stats().jitter_lost > before.jitter_lost; }));
  w.poll(cam);
  const uint64_t shown_at_loss = w.shown;
  ASSERT_TRUE(eventually([&] {
    w.poll(cam);
    return w.shown > shown_at_loss && cam.stats().frames_damaged > before.frames_damaged;
  }));
  const RtpCameraStats after = cam.stats();
  // The frames decoded but withheld until whole: up to the next sweep's start (at most 15; when
  // the first frame after the cut starts one, it may have lost its head: the one after, 15) and
  // through that sweep (14 more): at most two sweeps and a frame. Counted in frames the sender
  // encoded, not in time, which a loaded sender stretches (the capture times' gap is printed: it
  // also holds frames the sender dropped).
  const uint64_t damaged = after.frames_damaged - before.frames_damaged;
  const double gap_frames = double(w.newest_ns - last_whole_ns) * 1e-9 * kRateHz;
  std::printf(
      "one loss (%llu packets given up): %llu damaged frames not shown, whole frames again "
      "%.1f frame periods of capture time later, key frames %llu -> %llu, key-frame requests "
      "%llu -> %llu\n",
      static_cast<unsigned long long>(after.jitter_lost - before.jitter_lost),
      static_cast<unsigned long long>(damaged), gap_frames,
      static_cast<unsigned long long>(before.key_frames),
      static_cast<unsigned long long>(after.key_frames),
      static_cast<unsigned long long>(fb_before.key_frame_requests),
      static_cast<unsigned long long>(cam.feedback().key_frame_requests));
  EXPECT_LE(damaged, 2u * kRefreshFrames + 1);
  EXPECT_EQ(after.key_frames, before.key_frames) << "healed by a key frame, not by refresh";
  EXPECT_EQ(cam.feedback().key_frame_requests, fb_before.key_frame_requests) << "a PLI was sent";
  EXPECT_GE(damaged, 1u);
  // A PLI: the next 30 frames (two sweeps) bring no IDR (a PLI crosses in a few frames: the
  // key frame test's bound is 15).
  ASSERT_TRUE(cam.request_key_frame());
  const uint64_t arrived = cam.stats().frames_arrived;
  ASSERT_TRUE(eventually([&] {
    w.poll(cam);
    return cam.stats().frames_arrived >= arrived + 2 * kRefreshFrames;
  }));
  EXPECT_GE(cam.feedback().pli_sent, 1u);
  EXPECT_EQ(cam.stats().key_frames, after.key_frames) << "x264enc answered a PLI with an IDR";
  EXPECT_EQ(w.older_than_shown, 0u);
  expect_accounted(cam.stats());
}

struct LossRun {
  uint64_t arrived = 0, published = 0, older_than_shown = 0;
  double kbytes_per_s = 0.0;
  RtpCameraStats stats;
  RtpCamera::Feedback feedback;
  double share() const { return arrived == 0 ? 0.0 : double(published) / double(arrived); }
};

// hybrid-remote (intra refresh or the default) through `loss`, for kFrames frames after a
// warm-up; counted by frames that reached this host, so a loaded machine runs the same cell.
LossRun run(double loss, bool intra_refresh, uint64_t frames) {
  constexpr uint64_t kWarmUpFrames = 30;
  LossRun r;
  const uint16_t port = testing::free_rtp_port();
  EXPECT_NE(port, 0);
  RtpCamera cam(camera_config(port, loss));
  cam.negotiate({640, 480, {}, 0.0});
  cam.start();
  Watch w;
  int64_t window_ns = INT64_MAX;
  auto drain = [&] {
    w.poll(cam);
    RtpFrameTiming t;
    while (cam.pop_timing(t))
      if (t.arrival_ns >= window_ns) ++r.published;
  };
  {
    testing::ChildProcess remote(remote_to(port, intra_refresh));
    EXPECT_TRUE(eventually([&] {
      drain();
      return cam.stats().frames_arrived >= kWarmUpFrames;
    }));
    const RtpCameraStats before = cam.stats();
    window_ns = monotonic_now_ns();
    EXPECT_TRUE(eventually([&] {
      drain();
      return cam.stats().frames_arrived >= before.frames_arrived + frames;
    }));
    const RtpCameraStats end = cam.stats();
    r.arrived = end.frames_arrived - before.frames_arrived;
    r.kbytes_per_s = double(end.bytes - before.bytes) / 1e3 /
                     std::max(1e-3, double(monotonic_now_ns() - window_ns) * 1e-9);
  }  // killed
  EXPECT_TRUE(eventually([&] {
    drain();
    return cam.state() == SourceState::kStalled;
  }));
  drain();
  r.stats = cam.stats();
  r.feedback = cam.feedback();
  r.older_than_shown = w.older_than_shown;
  return r;
}

void print(const char* what, double loss, const LossRun& r) {
  std::printf(
      "| %s | %.0f %% | %llu / %llu | %.1f %% | %.0f | %llu | %llu | %llu | %llu | %llu |\n", what,
      loss * 100, static_cast<unsigned long long>(r.published),
      static_cast<unsigned long long>(r.arrived), r.share() * 100, r.kbytes_per_s,
      static_cast<unsigned long long>(r.stats.jitter_lost),
      static_cast<unsigned long long>(r.stats.key_frames),
      static_cast<unsigned long long>(r.feedback.key_frame_requests),
      static_cast<unsigned long long>(r.stats.frames_damaged),
      static_cast<unsigned long long>(r.older_than_shown));
  std::fflush(stdout);
}

const char* kHeader =
    "| sender | loss | shown / reached | share | kB/s | packets given up | key frames decoded | "
    "key-frame requests | damaged (not shown) | old shown as new |\n|---|---|---|---|---|---|---|"
    "---|---|---|\n";

// At 2 % loss without repair: damaged frames are counted and never shown, no key frame after the
// first (the station may ask for one before it saw the first sweep's recovery point; x264enc
// answers with a sweep), nothing old as new. (Few frames are shown: at ~13 packets a frame,
// 15 frames in a row without a loss are rare; DISABLED_Measure gives the shares.)
TEST(RemoteIntraRefresh, UnderRandomLossDamagedFramesAreCountedNotShownAndNoKeyFrameUnasked) {
  const LossRun r = run(0.02, true, 150);
  std::printf("%s", kHeader);
  print("intra refresh", 0.02, r);
  EXPECT_TRUE(r.stats.heals_by_refresh);
  EXPECT_GT(r.stats.jitter_lost, 0u);
  EXPECT_GT(r.stats.frames_damaged, 0u) << "losses, but no frame judged damaged";
  EXPECT_LE(r.stats.key_frames, 1u);  // the first IDR, unless a loss hit it, and no other
  EXPECT_EQ(r.older_than_shown, 0u);
  expect_accounted(r.stats);
}

// Measurement, not a check (run with --gtest_also_run_disabled_tests): intra refresh against the
// default sender at 1 and 5 % loss, retransmission off, same frames.
TEST(RemoteIntraRefresh, DISABLED_MeasureSharesAndBytesAgainstTheDefault) {
  std::printf("%s", kHeader);
  for (double loss : {0.0, 0.01, 0.05})
    for (bool ir : {false, true}) print(ir ? "intra refresh" : "default", loss, run(loss, ir, 300));
}

}  // namespace
}  // namespace hd::drivers
