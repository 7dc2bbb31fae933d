// Drawing an overlay (ghost frustum, arrow, HUD strip) allocates nothing: the per-frame path of
// the CPU compositor's draw_overlay, counted by hd_allocation_counter's operator new.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "core/allocation_counter.h"
#include "drivers/mock/mock_camera.h"
#include "drivers/mock/mock_pose_source.h"
#include "render/compositor/cpu_compositor.h"
#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"
#include "render/overlay/overlay_painter.h"
#include "station/frame/station_frame.h"
#include "station/prediction/constant_velocity_predictor.h"
#include "support/small_station.h"

namespace hd::station {
namespace {

TEST(OverlayNoAllocation, HundredOverlayDrawsAllocateNothing) {
  const core::Pinhole eye = core::Pinhole::centred(300.0, 320, 240);
  const render::GuidanceCamera cam{
      core::Pinhole::centred(250.0, 160, 120),
      {Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix(),
       {0.3, -0.05, -0.2}},  // partly behind the eye: near-plane clipping runs
      1.2};
  render::HudStrip hud(320, 18);
  hud.set_text("frame 12  MTP swap 9.5 ms  display 12.5 ms");  // outside the counted path
  render::CpuCompositor compositor(1);
  render::ImageRgba8 out;
  out.allocate(640, 240);
  const std::vector<uint8_t> blank = out.data;

  hd::core::reset_counted_allocations();
  hd::core::count_allocations_on_this_thread(true);
  for (int i = 0; i < 100; ++i) {
    const core::Pose T_world_eye{
        Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitY()).toRotationMatrix(),
        {0.0, 0.0, 0.002 * i}};
    render::Overlay o;
    o.cue = guidance_toward_nearest(eye, T_world_eye, std::span(&cam, 1));
    o.eye = eye;
    o.T_world_eye = T_world_eye;
    o.hud = i % 2 == 0 ? &hud : nullptr;
    compositor.draw_overlay(o, {(i % 2) * 320, 0, 320, 240}, out);
  }
  hd::core::count_allocations_on_this_thread(false);
  EXPECT_EQ(hd::core::counted_allocations(), 0u);
  // It really drew: frustum or arrow in both eyes, HUD in the left one.
  int left = 0, right = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 640; ++x)
      if (out.pixel(x, y)[3] != 0) ++(x < 320 ? left : right);
  EXPECT_GT(left, 320 * 18);
  EXPECT_GT(right, 50);
  EXPECT_NE(out.data, blank);
}

// The station frame with a HUD line set and the head far from the only camera (synthetic view,
// guidance on): every tick draws frustum, arrow and HUD, and allocates nothing.
TEST(OverlayNoAllocation, StationFrameDrawsGuidanceAndHudWithoutAllocating) {
  drivers::MockCamera camera(test::small_camera_config());
  drivers::MockPoseSource pose(test::head_config(test::head_motion(
      // 1.3 m from the camera: synthetic only
      [](double t) { return Eigen::Vector3d(1.0 + 0.05 * t, -0.2, -0.8); },
      [](double) { return -0.4; })));
  test::StartedDevices devices(camera, pose);

  StationFrameConfig cfg = test::small_station_config(200);
  cfg.marking.style = core::MarkingStyle::kNone;  // the background stays (40, 40, 48)
  const drivers::CalibratedCamera cams[] = {
      {&camera, test::small_camera_intrinsics(), core::Pose::identity(), 2.0}};
  ConstantVelocityPredictor predictor;
  render::CpuCompositor compositor(1);
  render::MonotonicLoopClock clock;
  render::LatencyRecorder latency(200);
  StationFrame frame(cfg, cams, pose, predictor, compositor, nullptr, clock, latency);
  render::FrameLoop loop(render::FrameLoopConfig{240.0, 2'000'000, true}, clock);
  frame.set_hud_text("warming up");
  loop.run(20, frame);
  frame.set_hud_text(latency.hud_line());  // outside the counted ticks, as the run loop does
  hd::core::reset_counted_allocations();
  hd::core::count_allocations_on_this_thread(true);
  loop.run(100, frame);
  hd::core::count_allocations_on_this_thread(false);
  devices.stop();
  EXPECT_EQ(hd::core::counted_allocations(), 0u);

  // Every frame after the first head sample is guided (the devices spoke before the first tick).
  int guided = 0;
  for (const FrameRow& r : frame.rows()) guided += r.guidance;
  EXPECT_EQ(frame.rows().size(), 120u);
  EXPECT_EQ(guided, 120);
  // Eye 0's top-left holds the HUD strip: the background (40, 40, 48) darkened by alpha 160.
  const render::ImageRgba8& img = frame.image();
  const int strip_h = frame.hud().image().height;
  ASSERT_EQ(frame.hud().image().width, 160);
  EXPECT_EQ(img.pixel(0, 0)[0], (95 * 40 + 127) / 255);
  // Eye 1 (x >= 160) has no strip.
  EXPECT_NE(img.pixel(160 + 5, 1)[0], (95 * 40 + 127) / 255);
  // Both eyes show frustum or arrow pixels.
  int overlay_left = 0, overlay_right = 0;
  for (int y = strip_h; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const uint8_t* p = img.pixel(x, y);
      const bool cue =
          (p[0] == 0 && p[1] == 255 && p[2] == 255) || (p[0] == 255 && p[1] == 220 && p[2] == 0);
      (x < 160 ? overlay_left : overlay_right) += cue;
    }
  EXPECT_GT(overlay_left, 30);
  EXPECT_GT(overlay_right, 30);
}

}  // namespace
}  // namespace hd::station
