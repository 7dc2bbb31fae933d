// A station-like frame with the overlay: the demo workspace seen from an eye that has wandered
// away from the camera (synthetic view only), the camera's ghost frustum, the guidance arrow and
// the HUD line. Checks that the overlay shows up over a textured picture where the geometry says;
// with HD_OVERLAY_PNG=<path> it also writes the frame (docs/overlay.md's figure).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "render/compositor/cpu_compositor.h"
#include "render/compositor/demo_scene.h"
#include "render/latency/latency_recorder.h"
#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"

namespace hd::render {
namespace {

core::Pose look(double yaw_deg, double pitch_deg, const Eigen::Vector3d& t) {
  const double k = std::numbers::pi / 180.0;
  return {(Eigen::AngleAxisd(yaw_deg * k, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(pitch_deg * k, Eigen::Vector3d::UnitX()))
              .toRotationMatrix(),
          t};
}

void write_png(const ImageRgba8& img, const std::string& path) {
  const cv::Mat rgba(img.height, img.width, CV_8UC4, const_cast<uint8_t*>(img.data.data()),
                     static_cast<std::size_t>(img.stride_bytes));
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  const std::string tmp = path + ".tmp.png";
  ASSERT_TRUE(cv::imwrite(tmp, bgr)) << "cannot write " << tmp;
  std::filesystem::rename(tmp, path);
  std::printf("    wrote %s\n", path.c_str());
}

TEST(OverlayFigure, GhostFrustumArrowAndHudOverTheDemoWorkspace) {
  const SyntheticScene scene = make_demo_scene();
  const core::Pinhole eye = core::Pinhole::centred(520.0, 640, 480);
  const core::Pose T_world_eye = look(32.0, -10.0, {-0.9, -0.3, -1.0});
  const GuidanceCamera cam{core::Pinhole::centred(420.0, 480, 360),
                           look(0.0, -5.0, {0.0, -0.1, -0.2}), 1.3};

  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.T_world_eye = T_world_eye;
  req.transition = {core::Variant::kSynthetic, 0.0, 1.0};
  req.marking.style = core::MarkingStyle::kFrame;
  req.viewport = {0, 0, 640, 480};
  CpuCompositor compositor(1);
  ImageRgba8 base;
  base.allocate(640, 480);
  compositor.draw(req, base);

  // The HUD line as the station formats it, from one recorded frame.
  LatencyRecorder latency(4);
  LatencyRecord r;
  r.frame = 1234;
  r.pose_sample_ns = 1'000'000'000;
  r.render_start_ns = 1'004'000'000;
  r.render_end_ns = 1'006'500'000;
  r.swap_ns = 1'009'500'000;
  r.predicted_display_ns = 1'012'500'000;
  latency.record(r);
  HudStrip hud(640, 20);
  hud.set_text(latency.hud_line());

  Overlay o;
  o.cue = guidance_toward_nearest(eye, T_world_eye, std::span(&cam, 1));
  o.eye = eye;
  o.T_world_eye = T_world_eye;
  o.near_m = req.near_m;
  o.hud = &hud;
  ASSERT_TRUE(o.cue.active);
  ImageRgba8 img = base;
  compositor.draw_overlay(o, req.viewport, img);

  // Each frustum corner that projects inside the picture (away from the HUD strip) has a
  // frustum-coloured pixel within one pixel.
  int corners_seen = 0;
  for (int k = 1; k <= 4; ++k) {
    const Eigen::Vector3d p =
        T_world_eye.to_camera(o.cue.frustum_world[static_cast<std::size_t>(k)]);
    if (p.z() <= req.near_m) continue;
    const Eigen::Vector2d q = eye.project(p);
    if (q.x() < 2 || q.y() < 22 || q.x() > 638 || q.y() > 478) continue;
    bool found = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const uint8_t* px = img.pixel(static_cast<int>(q.x()) + dx, static_cast<int>(q.y()) + dy);
        found |=
            px[0] == o.frustum_rgb[0] && px[1] == o.frustum_rgb[1] && px[2] == o.frustum_rgb[2];
      }
    EXPECT_TRUE(found) << "corner " << k << " at " << q.transpose();
    ++corners_seen;
  }
  EXPECT_GE(corners_seen, 2) << "the figure should show the frustum's far rectangle";
  int frustum_px = 0, arrow_px = 0, strip_changed = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      const uint8_t* p = img.pixel(x, y);
      const uint8_t* b = base.pixel(x, y);
      const bool changed = !std::equal(p, p + 4, b);
      if (y < 20) {
        strip_changed += changed;
        continue;
      }
      frustum_px += changed && p[0] == o.frustum_rgb[0] && p[1] == o.frustum_rgb[1] &&
                    p[2] == o.frustum_rgb[2];
      arrow_px +=
          changed && p[0] == o.arrow_rgb[0] && p[1] == o.arrow_rgb[1] && p[2] == o.arrow_rgb[2];
    }
  EXPECT_GT(frustum_px, 300);
  EXPECT_GT(arrow_px, 300);
  EXPECT_GT(strip_changed, 640 * 20 * 9 / 10);

  if (const char* path = std::getenv("HD_OVERLAY_PNG")) write_png(img, path);
}

}  // namespace
}  // namespace hd::render
