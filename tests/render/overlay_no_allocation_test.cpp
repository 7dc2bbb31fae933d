// Drawing an overlay (ghost frustum, arrow, HUD strip) allocates nothing: the per-frame path of
// the CPU compositor's draw_overlay, counted by hd_allocation_counter's operator new.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "core/allocation_counter.h"
#include "render/compositor/cpu_compositor.h"
#include "render/overlay/hud_strip.h"
#include "render/overlay/overlay_painter.h"
#include "render/selection/guidance_cue.h"

namespace hd::render {
namespace {

TEST(OverlayNoAllocation, HundredOverlayDrawsAllocateNothing) {
  const core::Pinhole eye = core::Pinhole::centred(300.0, 320, 240);
  const GuidanceCamera cam{core::Pinhole::centred(250.0, 160, 120),
                           {Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                            {0.3, -0.05, -0.2}},  // partly behind the eye: near-plane clipping runs
                           1.2};
  HudStrip hud(320, 18);
  hud.set_text("frame 12  MTP swap 9.5 ms  display 12.5 ms");  // outside the counted path
  CpuCompositor compositor(1);
  ImageRgba8 out;
  out.allocate(640, 240);
  const std::vector<uint8_t> blank = out.data;

  hd::core::reset_counted_allocations();
  hd::core::count_allocations_on_this_thread(true);
  for (int i = 0; i < 100; ++i) {
    const core::Pose T_world_eye{
        Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitY()).toRotationMatrix(),
        {0.0, 0.0, 0.002 * i}};
    Overlay o;
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

}  // namespace
}  // namespace hd::render
