// The CPU reference compositor's marks of the synthetic part against hand-computed colours: the
// variant's frame, desaturation and the checker.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "support/cpu_compositor_scenes.h"

namespace {

using namespace hd::render::test;

TEST(CpuCompositor, FrameMarkPaintsTheBorderInTheVariantColour) {
  const Pinhole cam = pinhole(100.0, 80, 60);
  SyntheticScene scene;
  scene.background_rgb = {1, 2, 3};
  for (Variant variant : {Variant::kVideo, Variant::kHybrid, Variant::kSynthetic}) {
    CpuCompositor comp;
    ImageRgba8 out;
    out.allocate(100, 70);  // the eye's viewport sits inside a larger picture
    CompositeRequest req;
    req.scene = &scene;
    req.eye = cam;
    req.transition = {variant, 0.0, 1.0};
    req.marking.style = MarkingStyle::kFrame;
    req.marking.frame_width_px = 5;
    req.viewport = {12, 7, 80, 60};
    comp.draw(req, out);
    const auto& fc = req.marking.frame_colour(variant);
    int frame_px = 0, inner_px = 0, untouched = 0;
    for (int y = 0; y < 70; ++y) {
      for (int x = 0; x < 100; ++x) {
        const uint8_t* o = out.pixel(x, y);
        const int vx = x - 12, vy = y - 7;
        if (vx < 0 || vy < 0 || vx >= 80 || vy >= 60) {
          untouched += (o[0] == 0 && o[1] == 0 && o[2] == 0 && o[3] == 0) ? 1 : 0;
        } else if (vx < 5 || vy < 5 || vx >= 75 || vy >= 55) {
          frame_px += same_rgb(o, fc.r, fc.g, fc.b) ? 1 : 0;
        } else {
          inner_px += same_rgb(o, 1, 2, 3) ? 1 : 0;
        }
      }
    }
    EXPECT_EQ(frame_px, 80 * 60 - 70 * 50);
    EXPECT_EQ(inner_px, 70 * 50);
    EXPECT_EQ(untouched, 100 * 70 - 80 * 60);
  }
}

TEST(CpuCompositor, DesaturationTurnsTheSyntheticPartGreyAndLeavesVideoAlone) {
  const Pinhole cam = pinhole(100.0, 80, 60);
  const Pinhole real = pinhole(100.0, 40, 60);  // covers the left half of the eye's view
  Pinhole real_left = real;
  real_left.cx = 40.0;  // the real image spans eye u in [0, 40]
  const Frame frame = uniform_frame(40, 60, 10, 200, 90);
  SyntheticScene scene;
  scene.background_rgb = {200, 100, 50};
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(80, 60);
  CompositeRequest req = video_request(cam, &frame, real_left);
  req.scene = &scene;
  req.transition = {Variant::kHybrid, 1.0, 0.0};
  req.marking.style = MarkingStyle::kDesaturate;
  req.marking.synthetic_desaturation = 1.0;
  comp.draw(req, out);
  EXPECT_TRUE(same_rgb(out.pixel(10, 30), 10, 200, 90));  // video untouched
  // Rec. 601 luma of (200, 100, 50) = 124.2.
  EXPECT_TRUE(same_rgb(out.pixel(60, 30), 124, 124, 124));
  req.marking.synthetic_desaturation = 0.5;  // halfway: (162.1, 112.1, 87.1)
  comp.draw(req, out);
  EXPECT_TRUE(same_rgb(out.pixel(60, 30), 162, 112, 87));
}

TEST(CpuCompositor, CheckerRaisesAndLowersAlternateCellsOfTheSyntheticPart) {
  const Pinhole cam = pinhole(100.0, 64, 64);
  SyntheticScene scene;
  scene.background_rgb = {100, 100, 100};
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(64, 64);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = cam;
  req.marking.style = MarkingStyle::kChecker;
  req.marking.checker_cell_px = 16;
  req.marking.checker_contrast = 0.5;  // +-0.25 of full scale: 100 +- 63.75
  req.viewport = {0, 0, 64, 64};
  comp.draw(req, out);
  EXPECT_TRUE(same_rgb(out.pixel(0, 0), 164, 164, 164));
  EXPECT_TRUE(same_rgb(out.pixel(15, 15), 164, 164, 164));
  EXPECT_TRUE(same_rgb(out.pixel(16, 0), 36, 36, 36));
  EXPECT_TRUE(same_rgb(out.pixel(0, 16), 36, 36, 36));
  EXPECT_TRUE(same_rgb(out.pixel(16, 16), 164, 164, 164));
}

}  // namespace
