// The whole station frame (mock camera + mock pose source + CPU compositor + prediction +
// selection + transition + latency) allocates nothing on the render thread after warm-up.
// hd_allocation_counter counts operator new on this thread while enabled.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "core/allocation_counter.h"
#include "drivers/mock/mock_camera.h"
#include "drivers/mock/mock_pose_source.h"
#include "render/compositor/cpu_compositor.h"
#include "station/frame/station_frame.h"
#include "station/model/model_updater.h"
#include "station/prediction/kalman_predictor.h"
#include "station/video/camera_pipeline.h"
#include "support/small_station.h"

namespace hd::station {
namespace {

// Counts only while a frame runs on this thread.
class CountingWork final : public render::FrameWork {
 public:
  explicit CountingWork(render::FrameWork& inner) : inner_(inner) {}
  void tick(const render::FrameTiming& t) override {
    hd::core::count_allocations_on_this_thread(counting);
    inner_.tick(t);
    hd::core::count_allocations_on_this_thread(false);
  }
  bool counting = false;

 private:
  render::FrameWork& inner_;
};

// 300 ticks of a station with one mock camera whose video is laid as `view` says.
void three_hundred_ticks(core::VideoView view) {
  drivers::MockCamera camera(test::small_camera_config());
  // Head sways 20 cm sideways around the camera position: video, hybrid and synthetic all occur.
  drivers::MockPoseSource pose(test::head_config(test::head_motion(
      [](double t) { return Eigen::Vector3d(0.2 * std::sin(2.0 * M_PI * 1.5 * t), 0.0, 0.0); },
      [](double t) { return 0.3 * std::sin(2.0 * M_PI * t); })));
  test::StartedDevices devices(camera, pose);

  const StationFrameConfig cfg =
      test::small_station_config(400);  // m swings ~3..36 with this motion
  const drivers::CalibratedCamera cams[] = {
      {&camera, test::small_camera_intrinsics(), core::Pose::identity(), 2.0, 0.0, view}};
  const render::SyntheticScene scene = test::checker_quad_scene();
  KalmanPredictor predictor;
  render::CpuCompositor compositor(1);
  render::MonotonicLoopClock clock;
  render::LatencyRecorder latency(400);
  StationFrame frame(cfg, cams, pose, predictor, compositor, &scene, clock, latency);
  CountingWork work(frame);
  render::FrameLoop loop(render::FrameLoopConfig{240.0, 2'000'000, true}, clock);

  loop.run(30, work);  // warm-up: first draws size the compositor's buffers
  work.counting = true;
  hd::core::reset_counted_allocations();
  loop.run(300, work);
  work.counting = false;
  const uint64_t allocations = hd::core::counted_allocations();
  // The HUD line is formatted every frame in the windowed station: it must not allocate either.
  hd::core::count_allocations_on_this_thread(true);
  const auto hud = latency.hud_line();
  hd::core::count_allocations_on_this_thread(false);
  devices.stop();

  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(hd::core::counted_allocations(), 0u) << hud;
  // The loop really ran the pipeline: frames drawn, poses consumed, video fetched.
  EXPECT_EQ(frame.rows().size(), 330u);
  // Two eyes per frame, none refused: a request the compositor rejects (request_check.h) is
  // counted, not drawn. An ASan build of 2026-11-22 02:48 once saw frames_drawn 0 here; it never
  // reproduced at any commit (docs/video-and-model.md), so a repeat must say which count it was.
  EXPECT_EQ(compositor.stats().requests_rejected, 0u);
  EXPECT_EQ(compositor.stats().video_frames_rejected, 0u);
  EXPECT_EQ(compositor.stats().frames_drawn, 660u)
      << "rejected " << compositor.stats().requests_rejected << ", video frames rejected "
      << compositor.stats().video_frames_rejected;
  EXPECT_GT(frame.pose_history().accepted(), 100u);
  EXPECT_GT(frame.frames_fetched()[0], 20u);
  EXPECT_EQ(latency.total_recorded(), 330u);
  int video = 0, synthetic = 0;
  for (const FrameRow& r : frame.rows()) {
    video += r.variant == core::Variant::kVideo;
    synthetic += r.variant == core::Variant::kSynthetic;
  }
  EXPECT_GT(video, 0);
  EXPECT_GT(synthetic, 0);
  // Model-depth really ran: its depth map of the (unchanging) model was drawn once.
  EXPECT_EQ(compositor.stats().camera_depth_renders,
            view == core::VideoView::kModelDepth ? 1u : 0u);
}

TEST(LoopNoAllocation, ThreeHundredStationTicksAllocateNothingAfterWarmUp) {
  three_hundred_ticks(core::VideoView::kPlane);
}

// The other video views add per-frame work to the tick (the fitted plane's median, the
// model-depth rows and seen test): none of it allocates either.
TEST(LoopNoAllocation, FittedPlaneTicksAllocateNothingAfterWarmUp) {
  three_hundred_ticks(core::VideoView::kFittedPlane);
}

TEST(LoopNoAllocation, ModelDepthTicksAllocateNothingAfterWarmUp) {
  three_hundred_ticks(core::VideoView::kModelDepth);
}

// The same station reading an undistorting camera pipeline and drawing the delayed model that a
// model updater re-textures from that camera 20 times a second: the tick still allocates nothing,
// and the latency log carries the model's age.
TEST(LoopNoAllocation, StationWithCameraPipelineAndModelUpdaterAllocatesNothing) {
  core::Pinhole cam_k = test::small_camera_intrinsics();
  cam_k.distortion = {-0.2, 0.05, 0.0, 0.0, 0.0};
  cam_k.distortion_count = 5;
  drivers::MockCamera camera(test::small_camera_config());
  CameraPipeline pipeline(camera, {cam_k, 0.05, 200'000});
  drivers::MockPoseSource pose(test::head_config(test::head_motion(
      [](double t) { return Eigen::Vector3d(0.2 * std::sin(2.0 * M_PI * 1.5 * t), 0.0, 0.0); },
      [](double) { return 0.0; })));
  test::StartedDevices devices(pipeline, pose);

  const StationFrameConfig cfg = test::small_station_config(400);
  core::Pinhole undistorted = cam_k;
  undistorted.distortion_count = 0;
  const drivers::CalibratedCamera cams[] = {{&pipeline, undistorted, core::Pose::identity(), 2.0}};
  const render::SyntheticScene scene = test::checker_quad_scene();
  render::MonotonicLoopClock clock;
  const ModelCamera model_cams[] = {
      {&pipeline.model_frames(), undistorted, core::Pose::identity()}};
  ModelUpdaterConfig mc;
  mc.refresh_period_s = 0.05;
  mc.delay_s = 0.01;
  ModelUpdater updater(scene, model_cams, mc, clock);
  updater.start();
  KalmanPredictor predictor;
  render::CpuCompositor compositor(1);
  render::LatencyRecorder latency(400);
  StationFrame frame(cfg, cams, pose, predictor, compositor, &scene, clock, latency);
  frame.set_model_updater(&updater);
  CountingWork work(frame);
  render::FrameLoop loop(render::FrameLoopConfig{240.0, 2'000'000, true}, clock);

  loop.run(30, work);
  work.counting = true;
  hd::core::reset_counted_allocations();
  loop.run(300, work);
  work.counting = false;
  const uint64_t allocations = hd::core::counted_allocations();
  updater.stop();
  devices.stop();

  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(frame.frames_fetched()[0], 20u);
  EXPECT_GE(updater.stats().updates, 5u);  // ~1.4 s at 20 updates per second
  // Every frame drawn after the first update carries the model's capture time; its age is at
  // least the staleness delay (the frame was taken, then 10 ms passed before publishing).
  const render::LatencyStats age = latency.stats(render::LatencyMetric::kModelAge);
  EXPECT_GT(age.count, 100u);
  EXPECT_GE(age.p50_ms, 10.0);
  uint64_t previous_capture = 0;
  for (std::size_t i = 0; i < latency.size(); ++i) {
    const int64_t c = latency.at(i).model_capture_ns;
    EXPECT_GE(static_cast<uint64_t>(c), previous_capture);  // the model never goes back in time
    previous_capture = static_cast<uint64_t>(c);
  }
}

}  // namespace
}  // namespace hd::station
