// StationFrame with time as an input of the decision (issue 11 item 1): a camera whose newest
// frame is too old at the display time, or whose source stops streaming, is not shown as live
// video; it leaves through the transition and comes back with its first new frame. Ticks are
// driven with explicit timings (no loop, no clock): nothing here depends on how fast the
// machine is.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <thread>
#include <vector>

#include "drivers/mock/mock_pose_source.h"
#include "render/compositor/cpu_compositor.h"
#include "render/loop/stepped_clock.h"
#include "station/frame/station_frame.h"
#include "station/prediction/kalman_predictor.h"
#include "station/video/camera_pipeline.h"
#include "support/small_station.h"

namespace hd::station {
namespace {

constexpr int64_t kMs = 1'000'000;

// A camera the test publishes into by hand, with a state it sets. Every method a device thread
// would spend time in (open, start, stop, pop_format_event, dropped_frames) takes `device_lock`,
// as a driver busy in a long device call would; frames() and state() never do.
class HandCamera final : public drivers::CameraSource {
 public:
  explicit HandCamera(int w, int h) {
    drivers::Frame proto;
    proto.allocate_rgba(w, h);
    mailbox_ = std::make_unique<drivers::Mailbox<drivers::Frame>>(proto);
  }
  std::string id() const override { return "hand"; }
  void open() override { std::lock_guard<std::mutex> l(device_lock); }
  void start() override { std::lock_guard<std::mutex> l(device_lock); }
  void stop() override { std::lock_guard<std::mutex> l(device_lock); }
  bool pop_format_event(drivers::FormatEvent&) override {
    std::lock_guard<std::mutex> l(device_lock);
    return false;
  }
  uint64_t dropped_frames() const override {
    std::lock_guard<std::mutex> l(device_lock);
    return 0;
  }
  drivers::SourceState state() const override { return state_.load(); }
  drivers::Mailbox<drivers::Frame>& frames() override { return *mailbox_; }

  void publish(int64_t exposure_ns) {
    drivers::Frame& f = mailbox_->write_slot();
    for (std::size_t i = 0; i < f.data.size(); ++i) f.data[i] = static_cast<uint8_t>(200);
    f.host_timestamp_ns = exposure_ns;
    f.sequence = ++sequence_;
    mailbox_->publish();
  }
  void set_state(drivers::SourceState s) { state_.store(s); }

  mutable std::mutex device_lock;

 private:
  std::unique_ptr<drivers::Mailbox<drivers::Frame>> mailbox_;
  std::atomic<drivers::SourceState> state_{drivers::SourceState::kStreaming};
  uint64_t sequence_ = 0;
};

// The tests set the scene's time themselves; StationFrame never sleeps.
using FixedClock = render::SteppedLoopClock;

// One 160x120 camera at the origin looking down +z, the head (never moving) at the origin too:
// m = 0, so whatever is not video is the age rule's doing.
struct Rig {
  explicit Rig(core::TransitionMode mode, double max_age_s, double tau_s = 0.15)
      : camera(160, 120), pose(test::head_config([](double t) {
          drivers::TrajectorySample s;
          s.t_s = t;
          return s;
        })) {
    cfg = test::small_station_config(1000);
    cfg.rig.eye = {test::small_camera_intrinsics(), test::small_camera_intrinsics()};
    cfg.transition.mode = mode;
    cfg.transition.time_constant_s = tau_s;
    cams.push_back(
        {&camera, test::small_camera_intrinsics(), core::Pose::identity(), 2.0, max_age_s});
    frame = std::make_unique<StationFrame>(cfg, cams, pose, predictor, compositor, &scene, clock,
                                           latency);
  }
  // Frame k of a 90 Hz loop starting at 1 s; the display is one period later.
  render::FrameTiming timing(uint64_t k) const {
    render::FrameTiming t;
    t.frame = k;
    t.start_ns = 1'000 * kMs + static_cast<int64_t>(k) * period_ns;
    t.deadline_ns = t.start_ns + period_ns;
    t.display_ns = t.deadline_ns;
    t.dt_s = k == 0 ? 0.0 : 1e-9 * static_cast<double>(period_ns);
    return t;
  }
  const FrameRow& tick(uint64_t k) {
    const render::FrameTiming t = timing(k);
    clock.set_ns(t.start_ns);
    frame->tick(t);
    return frame->last_row();
  }
  std::vector<CameraUsabilityEvent> events() {
    std::vector<CameraUsabilityEvent> out;
    CameraUsabilityEvent e;
    while (frame->pop_usability_event(e)) out.push_back(e);
    return out;
  }

  const int64_t period_ns = 11'111'111;
  HandCamera camera;
  drivers::MockPoseSource pose;
  StationFrameConfig cfg;
  std::vector<drivers::CalibratedCamera> cams;
  render::SyntheticScene scene = test::checker_quad_scene();
  KalmanPredictor predictor;
  render::CpuCompositor compositor{1};
  FixedClock clock;
  render::LatencyRecorder latency{1000};
  std::unique_ptr<StationFrame> frame;
};

TEST(FrameVideoAge, AFrozenFrameFadesOutOncePastItsBoundAndNothingOlderIsShown) {
  Rig rig(core::TransitionMode::kGlobalBlend, 0.1);
  rig.camera.publish(rig.timing(0).display_ns - 20 * kMs);  // 20 ms old at frame 0's display
  const FrameRow& first = rig.tick(0);
  EXPECT_EQ(first.variant, core::Variant::kVideo);
  EXPECT_NEAR(first.video_age_ms, 20.0, 1e-6);
  std::vector<CameraUsabilityEvent> ev = rig.events();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].usable);

  // No new frame: the one on screen ages by 11.1 ms a frame.
  double oldest_shown_ms = 0.0;
  uint64_t unusable_at = 0;
  int hybrid = 0;
  for (uint64_t k = 1; k < 60; ++k) {
    const FrameRow& r = rig.tick(k);
    const double age_ms = 20.0 + 11.111111 * static_cast<double>(k);
    if (r.variant != core::Variant::kSynthetic) {
      oldest_shown_ms = std::max(oldest_shown_ms, r.video_age_ms);
      EXPECT_NEAR(r.video_age_ms, age_ms, 1e-3);
    }
    hybrid += r.variant == core::Variant::kHybrid;
    if (age_ms < 100.0) {
      EXPECT_EQ(r.variant, core::Variant::kVideo) << k;
    }
    if (!rig.frame->usable(0) && unusable_at == 0) unusable_at = k;
  }
  // Unusable in the first frame at or past 100 ms (frame 8: 108.9 ms), then faded over
  // min(tau, max/2) = 50 ms: shown at most until 150 ms.
  EXPECT_EQ(unusable_at, 8u);
  EXPECT_GT(hybrid, 0);  // a blend fades out, it does not cut
  EXPECT_LT(oldest_shown_ms, 150.0);
  EXPECT_GT(oldest_shown_ms, 100.0);
  ev = rig.events();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_FALSE(ev[0].usable);
  EXPECT_EQ(ev[0].frame, 8u);
  EXPECT_NEAR(ev[0].video_age_s, 0.1089, 1e-4);
  EXPECT_GT(rig.frame->frames_stale_blocked(), 40u);
  // Every frame with video on screen recorded its video (latency.csv's age agrees).
  for (std::size_t i = 0; i < rig.latency.size(); ++i) {
    const render::LatencyRecord& l = rig.latency.at(i);
    if (l.video_ns != 0) {
      EXPECT_LT(l.predicted_display_ns - l.video_ns, 150 * kMs);
    }
  }

  // The camera's first new frame: usable in that same frame, fading in.
  rig.camera.publish(rig.timing(60).display_ns - 15 * kMs);
  const FrameRow& back = rig.tick(60);
  EXPECT_TRUE(rig.frame->usable(0));
  EXPECT_NE(back.variant, core::Variant::kSynthetic);
  EXPECT_EQ(back.camera, 0);
  EXPECT_NEAR(back.video_age_ms, 15.0, 1e-6);
  ev = rig.events();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].usable);
  EXPECT_EQ(ev[0].frame, 60u);
}

TEST(FrameVideoAge, AbruptModeSwitchesToSyntheticInTheFirstFramePastTheBound) {
  Rig rig(core::TransitionMode::kAbrupt, 0.1);
  rig.camera.publish(rig.timing(0).display_ns - 20 * kMs);
  for (uint64_t k = 0; k < 20; ++k) {
    const FrameRow& r = rig.tick(k);
    EXPECT_EQ(r.variant, k < 8 ? core::Variant::kVideo : core::Variant::kSynthetic) << k;
    if (k >= 8) {
      EXPECT_TRUE(std::isnan(r.video_age_ms));
    }
  }
}

TEST(FrameVideoAge, ASourceThatStopsStreamingIsLeftAtOnceWhileItsFrameIsStillYoung) {
  Rig rig(core::TransitionMode::kGlobalBlend, 0.5);
  for (uint64_t k = 0; k < 5; ++k) {
    rig.camera.publish(rig.timing(k).display_ns - 20 * kMs);
    EXPECT_EQ(rig.tick(k).variant, core::Variant::kVideo);
  }
  rig.camera.set_state(drivers::SourceState::kDisconnected);
  const FrameRow& r = rig.tick(5);
  EXPECT_FALSE(rig.frame->usable(0));
  EXPECT_EQ(r.variant, core::Variant::kHybrid);  // fading out with the transition's lag
  EXPECT_LT(r.w_video, 1.0);
  const std::vector<CameraUsabilityEvent> ev = rig.events();
  ASSERT_EQ(ev.size(), 2u);
  EXPECT_FALSE(ev[1].usable);
  EXPECT_EQ(ev[1].state, drivers::SourceState::kDisconnected);
  // ... and is gone before the frame it shows is older than 1.5 max_video_age.
  double oldest_ms = 0.0;
  for (uint64_t k = 6; k < 100; ++k) {
    const FrameRow& q = rig.tick(k);
    if (q.variant != core::Variant::kSynthetic) oldest_ms = std::max(oldest_ms, q.video_age_ms);
  }
  EXPECT_LT(oldest_ms, 750.0);
  EXPECT_EQ(rig.tick(100).variant, core::Variant::kSynthetic);
}

// Outages never reach the render thread (issue 11 item 4): the camera's device is stuck in a
// call (its lock held, as Aravis holds a dead camera for seconds), and the station's frames --
// read through the camera pipeline, as hybrid-station does -- keep running to the end. Were
// the tick to call anything of the device but frames() and state(), this test would hang.
TEST(FrameVideoAge, TicksRunWhileTheDeviceIsStuckInACall) {
  Rig rig(core::TransitionMode::kGlobalBlend, 0.1);
  CameraPipeline pipeline(rig.camera, {test::small_camera_intrinsics(), 0.5, 200'000});
  rig.cams[0].source = &pipeline;
  rig.frame = std::make_unique<StationFrame>(rig.cfg, rig.cams, rig.pose, rig.predictor,
                                             rig.compositor, &rig.scene, rig.clock, rig.latency);
  rig.camera.publish(rig.timing(0).display_ns - 20 * kMs);
  ASSERT_TRUE(pipeline.process_one());
  int shown = 0;
  for (uint64_t k = 0; k < 5; ++k) shown += rig.tick(k).variant != core::Variant::kSynthetic;
  std::unique_lock<std::mutex> stuck(rig.camera.device_lock);  // the device hangs from here on
  rig.camera.set_state(drivers::SourceState::kStalled);
  for (uint64_t k = 5; k < 200; ++k) rig.tick(k);
  stuck.unlock();
  EXPECT_EQ(rig.frame->last_row().frame, 199u);
  EXPECT_EQ(shown, 5);
  EXPECT_FALSE(rig.frame->usable(0));
}

}  // namespace
}  // namespace hd::station
