// A network camera without a calibration file (issue 12 item 1): the station's pipeline publishes
// none of its frames and the frame loop never uses it until a frame brings the sender's p_c and
// P_c; from then on it is measured and drawn with exactly those, and a new revision (the camera
// moved) replaces them. With a file, the stream's calibration wins and its distance from the
// file's is reported. Ticks are driven by hand: nothing depends on the machine's speed.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "drivers/mock/mock_pose_source.h"
#include "render/compositor/cpu_compositor.h"
#include "render/loop/stepped_clock.h"
#include "station/frame/station_frame.h"
#include "station/prediction/kalman_predictor.h"
#include "station/video/calibration_difference.h"
#include "station/video/camera_pipeline.h"
#include "support/small_station.h"

namespace hd::station {
namespace {

constexpr int64_t kMs = 1'000'000;

// A network camera as the pipeline sees it: frames published by hand, with or without the
// calibration their stream carried.
class HandNetworkCamera final : public drivers::CameraSource {
 public:
  HandNetworkCamera() {
    drivers::Frame proto;
    proto.allocate_rgba(160, 120);
    mailbox_ = std::make_unique<drivers::Mailbox<drivers::Frame>>(proto);
  }
  std::string id() const override { return "rtp://127.0.0.1:5600"; }
  void open() override {}
  void start() override {}
  void stop() override {}
  uint64_t dropped_frames() const override { return 0; }
  drivers::SourceState state() const override { return drivers::SourceState::kStreaming; }
  drivers::Mailbox<drivers::Frame>& frames() override { return *mailbox_; }

  void publish(int64_t exposure_ns, const drivers::FrameCalibration& c) {
    drivers::Frame& f = mailbox_->write_slot();
    for (uint8_t& b : f.data) b = 200;
    f.host_timestamp_ns = exposure_ns;
    f.sequence = ++sequence_;
    f.calibration = c;
    mailbox_->publish();
  }

 private:
  std::unique_ptr<drivers::Mailbox<drivers::Frame>> mailbox_;
  uint64_t sequence_ = 0;
};

// The tests set the scene's time themselves; StationFrame never sleeps.
using FixedClock = render::SteppedLoopClock;

drivers::FrameCalibration streamed(uint32_t revision, double cx_px, double x_m) {
  drivers::FrameCalibration c;
  c.present = true;
  c.revision = revision;
  c.p_c = test::small_camera_intrinsics();
  c.p_c.cx = cx_px;
  c.T_world_cam.t.x() = x_m;
  return c;
}

// The station's view of one network camera (no file: p_c invalid, no pose), the head still at
// the origin looking down +z like the camera at the origin.
struct Station {
  explicit Station(const core::Pinhole& file_p_c, const core::Pose& file_pose)
      : pose(test::head_config([](double t) {
          drivers::TrajectorySample s;
          s.t_s = t;
          return s;
        })) {
    CameraPipelineConfig pc;
    pc.p_c = file_p_c;
    pc.T_world_cam = file_pose;
    pc.compare_depth_m = 2.0;
    pc.model_period_s = 0.0;
    pc.calibration_from_stream = !file_p_c.valid();
    pipe = std::make_unique<CameraPipeline>(camera, pc);
    cfg = test::small_station_config(1000);
    cfg.rig.eye = {test::small_camera_intrinsics(), test::small_camera_intrinsics()};
    cams.push_back({pipe.get(), file_p_c, file_pose, 2.0, 0.1});
    frame = std::make_unique<StationFrame>(cfg, cams, pose, predictor, compositor, &scene, clock,
                                           latency);
  }
  render::FrameTiming timing(uint64_t k) const {
    render::FrameTiming t;
    t.frame = k;
    t.start_ns = 1'000 * kMs + static_cast<int64_t>(k) * 11'111'111;
    t.deadline_ns = t.start_ns + 11'111'111;
    t.display_ns = t.deadline_ns;
    t.dt_s = k == 0 ? 0.0 : 0.011111111;
    return t;
  }
  // A frame from the network captured 10 ms before frame k's display, through the pipeline,
  // then frame k.
  const FrameRow& frame_with(uint64_t k, const drivers::FrameCalibration& c) {
    camera.publish(timing(k).display_ns - 10 * kMs, c);
    EXPECT_TRUE(pipe->process_one());
    const render::FrameTiming t = timing(k);
    clock.set_ns(t.start_ns);
    frame->tick(t);
    return frame->last_row();
  }
  std::vector<CameraUsabilityEvent> usability() {
    std::vector<CameraUsabilityEvent> out;
    CameraUsabilityEvent e;
    while (frame->pop_usability_event(e)) out.push_back(e);
    return out;
  }
  std::vector<CalibrationEvent> calibrations() {
    std::vector<CalibrationEvent> out;
    CalibrationEvent e;
    while (pipe->pop_calibration_event(e)) out.push_back(e);
    return out;
  }

  HandNetworkCamera camera;
  std::unique_ptr<CameraPipeline> pipe;
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

core::Pose no_pose() {
  core::Pose p;
  p.R.setZero();
  return p;
}

TEST(FrameStreamCalibration, ACameraWithoutAFileIsUsableOnlyOnceItsCalibrationArrives) {
  Station s(core::Pinhole{}, no_pose());
  // Frames without a calibration: never published, never shown, the camera never usable.
  for (uint64_t k = 0; k < 10; ++k) {
    const FrameRow& r = s.frame_with(k, {});
    EXPECT_EQ(r.variant, core::Variant::kSynthetic) << k;
    EXPECT_EQ(r.camera, -1);
    EXPECT_FALSE(s.frame->usable(0));
  }
  EXPECT_EQ(s.pipe->uncalibrated(), 10u);
  EXPECT_EQ(s.pipe->processed(), 0u);
  EXPECT_EQ(s.pipe->stream_revision(), -1);
  EXPECT_TRUE(s.usability().empty());
  EXPECT_TRUE(s.calibrations().empty());
  EXPECT_FALSE(s.frame->camera(0).p_c.valid());

  // The sender's calibration (revision 3): the camera at the origin like the head, so its video
  // is shown, measured with the streamed cx.
  const drivers::FrameCalibration c3 = streamed(3, 80.0, 0.0);
  const FrameRow& r = s.frame_with(10, c3);
  EXPECT_TRUE(s.frame->usable(0));
  EXPECT_EQ(r.camera, 0);
  EXPECT_EQ(r.variant, core::Variant::kVideo);
  const double m3 = r.m;
  EXPECT_LT(m3, s.cfg.transition.m_t);
  EXPECT_EQ(s.frame->camera(0).p_c.cx, 80.0);
  EXPECT_EQ(s.frame->camera(0).p_c.fx, c3.p_c.fx);
  EXPECT_EQ(s.frame->camera(0).T_world_real.t, c3.T_world_cam.t);
  EXPECT_EQ(s.pipe->stream_revision(), 3);
  const auto u = s.usability();
  ASSERT_EQ(u.size(), 1u);
  EXPECT_TRUE(u[0].usable);
  EXPECT_EQ(u[0].frame, 10u);
  const auto ev = s.calibrations();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].first);
  EXPECT_EQ(ev[0].revision, 3u);
  EXPECT_EQ(ev[0].p_c.cx, 80.0);
  EXPECT_TRUE(std::isnan(ev[0].differs_from_file_px));
  // The published frame carries the calibration it was undistorted with.
  ASSERT_TRUE(s.pipe->frames().latest().calibration.present);

  // The camera moved 0.1 m sideways (revision 4): measured from there, m is larger now.
  const FrameRow& moved = s.frame_with(11, streamed(4, 80.0, 0.1));
  EXPECT_EQ(s.frame->camera(0).T_world_real.t.x(), 0.1);
  EXPECT_GT(moved.m, m3);
  const auto ev4 = s.calibrations();
  ASSERT_EQ(ev4.size(), 1u);
  EXPECT_FALSE(ev4[0].first);
  EXPECT_FALSE(ev4[0].intrinsics_changed);  // only the pose: no new undistortion
}

TEST(FrameStreamCalibration, WithAFileTheStreamWinsAndItsDistanceFromTheFileIsReported) {
  core::Pose file_pose;
  Station s(test::small_camera_intrinsics(), file_pose);
  // Before a calibration arrives the file's is used.
  const FrameRow& r0 = s.frame_with(0, {});
  EXPECT_EQ(r0.camera, 0);
  EXPECT_EQ(s.frame->camera(0).p_c.cx, 80.0);
  // The stream's principal point 2 px to the right: that is what the station uses from then on.
  s.frame_with(1, streamed(1, 82.0, 0.0));
  EXPECT_EQ(s.frame->camera(0).p_c.cx, 82.0);
  const auto ev = s.calibrations();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_TRUE(ev[0].intrinsics_changed);
  EXPECT_NEAR(ev[0].differs_from_file_px, 2.0, 1e-9);  // a moved principal point moves every pixel
}

TEST(CalibrationDifference, IsZeroForTheSameCalibrationAndFollowsClosedFormsOtherwise) {
  core::Pinhole p = core::Pinhole::centred(500, 640, 480);
  p.distortion = {-0.2, 0.05, 0.001, -0.001, 0.0};
  p.distortion_count = 5;
  const core::Pose P;
  EXPECT_NEAR(calibration_difference_px(p, P, p, P, 2.0), 0.0, 1e-6);
  // Without distortion a principal point 0.7 px lower moves every pixel by 0.7 px (with it, the
  // distortion's centre moves too, and the difference grows towards the corners).
  const core::Pinhole ideal = core::Pinhole::centred(500, 640, 480);
  core::Pinhole q = ideal;
  q.cy += 0.7;
  EXPECT_NEAR(calibration_difference_px(ideal, P, q, P, 2.0), 0.7, 1e-6);
  core::Pinhole pq = p;
  pq.cy += 0.7;
  EXPECT_GT(calibration_difference_px(p, P, pq, P, 2.0), 0.7);
  // A camera 0.01 m to the side, points 2 m away: f dx / d = 500 * 0.01 / 2 = 2.5 px.
  core::Pose moved;
  moved.t.x() = 0.01;
  EXPECT_NEAR(calibration_difference_px(ideal, P, ideal, moved, 2.0), 2.5, 1e-9);
  // Not a calibration: infinitely far.
  EXPECT_TRUE(std::isinf(calibration_difference_px(core::Pinhole{}, P, p, P, 2.0)));
}

}  // namespace
}  // namespace hd::station
