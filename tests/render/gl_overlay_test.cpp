// The GL compositor's overlay (ghost frustum, arrow, HUD strip) against the CPU painter on Mesa's
// llvmpipe (run under xvfb-run with LIBGL_ALWAYS_SOFTWARE=1). Lines may differ by rasterisation
// rules, so line pixels are compared with a 1-px dilation; everything else to 2 levels.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "render/compositor/cpu_compositor.h"
#include "render/gl/gl_compositor.h"
#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"
#include "support/gl_vs_cpu_test.h"

namespace hd::render {
namespace {

using core::Pinhole;
using core::Pose;

Pose turn(double yaw_rad, double pitch_rad, const Eigen::Vector3d& t) {
  return {(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitX()))
              .toRotationMatrix(),
          t};
}

bool is(const uint8_t* p, const std::array<uint8_t, 3>& c) {
  return p[0] == c[0] && p[1] == c[1] && p[2] == c[2];
}

// Every pixel of colour c in `a` has a pixel of colour c within one pixel (8-neighbourhood) in
// `b`; returns how many do not, and counts a's pixels of colour c in *n.
int unmatched(const ImageRgba8& a, const ImageRgba8& b, const std::array<uint8_t, 3>& c, int* n) {
  int missing = 0;
  *n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (!is(a.pixel(x, y), c)) continue;
      ++*n;
      bool found = false;
      for (int dy = -1; dy <= 1 && !found; ++dy)
        for (int dx = -1; dx <= 1 && !found; ++dx) {
          const int u = x + dx, v = y + dy;
          found = u >= 0 && v >= 0 && u < b.width && v < b.height && is(b.pixel(u, v), c);
        }
      missing += !found;
    }
  return missing;
}

// Largest channel difference over pixels not within one pixel of a line pixel in either picture.
int max_diff_off_lines(const ImageRgba8& a, const ImageRgba8& b, const Overlay& o) {
  auto line = [&](const ImageRgba8& img, int x, int y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int u = x + dx, v = y + dy;
        if (u < 0 || v < 0 || u >= img.width || v >= img.height) continue;
        const uint8_t* p = img.pixel(u, v);
        if (is(p, o.frustum_rgb) || is(p, o.arrow_rgb)) return true;
      }
    return false;
  };
  int worst = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (line(a, x, y) || line(b, x, y)) continue;
      for (int k = 0; k < 4; ++k)
        worst = std::max(worst, std::abs(int(a.pixel(x, y)[k]) - int(b.pixel(x, y)[k])));
    }
  return worst;
}

class GlOverlayTest : public test::GlVsCpuTest {
 protected:
  CompositeRequest request(const Pose& T_world_eye, const Viewport& vp) const {
    CompositeRequest r;
    r.scene = &scene_;
    r.eye = eye_;
    r.T_world_eye = T_world_eye;
    r.viewport = vp;
    r.marking.style = core::MarkingStyle::kNone;
    return r;
  }

  Overlay overlay(const Pose& T_world_eye, const GuidanceCamera& cam) const {
    Overlay o;
    o.cue = guidance_toward_nearest(eye_, T_world_eye, std::span(&cam, 1));
    o.eye = eye_;
    o.T_world_eye = T_world_eye;
    o.near_m = 0.05;
    return o;
  }

  void expect_lines_match(const Overlay& o, int min_line_pixels) {
    for (const auto& c : {o.frustum_rgb, o.arrow_rgb}) {
      int n_cpu = 0, n_gl = 0;
      const int cpu_missing_in_gl = unmatched(cpu_out_, gl_out_, c, &n_cpu);
      const int gl_missing_in_cpu = unmatched(gl_out_, cpu_out_, c, &n_gl);
      std::printf("    colour (%d,%d,%d): CPU %d px, GL %d px, unmatched %d / %d\n", c[0], c[1],
                  c[2], n_cpu, n_gl, cpu_missing_in_gl, gl_missing_in_cpu);
      EXPECT_GE(n_cpu, min_line_pixels);
      EXPECT_EQ(cpu_missing_in_gl, 0);
      EXPECT_EQ(gl_missing_in_cpu, 0);
      EXPECT_NEAR(n_gl, n_cpu, 0.1 * n_cpu + 4);
    }
    EXPECT_LE(max_diff_off_lines(cpu_out_, gl_out_, o), 2);
  }

  Pinhole eye_ = Pinhole::centred(330.0, 400, 300);
  SyntheticScene scene_;  // background only: overlay pixels stand out
};

TEST_F(GlOverlayTest, FrustumAndArrowMatchTheCpuPainter) {
  const Pose T_world_eye = turn(0.1, -0.05, {0.0, 0.0, 0.0});
  const GuidanceCamera cam{Pinhole::centred(300.0, 320, 240), turn(-0.25, 0.1, {0.3, -0.1, 0.5}),
                           1.4};
  const Overlay o = overlay(T_world_eye, cam);
  ASSERT_TRUE(o.cue.active);
  draw_both(request(T_world_eye, {0, 0, 400, 300}), 400, 300, &o);
  expect_lines_match(o, 60);
}

TEST_F(GlOverlayTest, FrustumCrossingTheNearPlaneMatchesTheCpuPainter) {
  // The camera sits beside and slightly behind the eye, looking across its view: some edges
  // cross the eye's near plane and are clipped in 3D by both (the same geometry).
  const Pose T_world_eye = Pose::identity();
  const GuidanceCamera cam{Pinhole::centred(250.0, 320, 240), turn(-0.9, 0.0, {0.4, 0.05, -0.1}),
                           1.5};
  const Overlay o = overlay(T_world_eye, cam);
  ASSERT_TRUE(o.cue.active);
  OverlaySegments segs;
  overlay_geometry(o, {0, 0, 400, 300}, segs);
  Eigen::Vector3d c = T_world_eye.to_camera(cam.T_world_real.t);
  ASSERT_LT(c.z(), 0.05) << "the camera centre should be behind the eye's near plane";
  ASSERT_GT(segs.frustum_count, 0);
  draw_both(request(T_world_eye, {0, 0, 400, 300}), 400, 300, &o);
  expect_lines_match(o, 60);
}

TEST_F(GlOverlayTest, HudStripIsInTheReadBackAndMatchesTheCpuBlend) {
  HudStrip hud(400, 20);
  hud.set_text("frame 41  MTP swap 9.5 ms  display 12.5 ms");
  Overlay o;
  o.hud = &hud;
  const CompositeRequest req = request(Pose::identity(), {0, 0, 400, 300});
  const uint64_t uploads = gl_->hud_uploads();
  draw_both(req, 400, 300, &o);
  EXPECT_EQ(gl_->hud_uploads(), uploads + 1);
  int worst = 0, dark = 0, bright = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) {
      const uint8_t* g = gl_out_.pixel(x, y);
      for (int k = 0; k < 4; ++k) worst = std::max(worst, std::abs(g[k] - cpu_out_.pixel(x, y)[k]));
      if (y >= 20) {
        // Below the strip: the background, untouched.
        ASSERT_TRUE(g[0] == 40 && g[1] == 40 && g[2] == 48) << x << "," << y;
        continue;
      }
      dark += g[0] < 30;     // translucent black over the background (40 -> 15)
      bright += g[0] > 150;  // glyphs
    }
  std::printf("    HUD: max |GL - CPU| %d, strip pixels dark %d, bright %d\n", worst, dark, bright);
  EXPECT_LE(worst, 2);
  EXPECT_GT(dark, 400 * 20 / 2);
  EXPECT_GT(bright, 50);

  // Same text again: no re-upload; new text: one.
  gl_->draw(req, gl_out_);
  gl_->draw_overlay(o, req.viewport, gl_out_);
  EXPECT_EQ(gl_->hud_uploads(), uploads + 1);
  hud.set_text("frame 42");
  gl_->draw(req, gl_out_);
  gl_->draw_overlay(o, req.viewport, gl_out_);
  EXPECT_EQ(gl_->hud_uploads(), uploads + 2);
  cpu_.draw(req, cpu_out_);
  cpu_.draw_overlay(o, req.viewport, cpu_out_);
  int worst2 = 0;
  for (std::size_t i = 0; i < gl_out_.data.size(); ++i)
    worst2 = std::max(worst2, std::abs(gl_out_.data[i] - cpu_out_.data[i]));
  EXPECT_LE(worst2, 2);
}

TEST_F(GlOverlayTest, StereoRightEyeOverlayMatchesTheCpuPainter) {
  // Right eye (viewport x = 400) gets the frustum, arrow and HUD over a stereo picture; the
  // geometry's viewport offset and the HUD quad's origin must agree between CPU and GL.
  const Pose T_left = turn(0.0, 0.0, {-0.032, 0.0, 0.0});
  const Pose T_right = turn(0.0, 0.0, {0.032, 0.0, 0.0});
  const GuidanceCamera cam{Pinhole::centred(300.0, 320, 240), turn(0.3, 0.0, {-0.5, 0.0, 0.3}),
                           2.0};
  HudStrip hud(400, 20);
  hud.set_text("right eye");
  Overlay o = overlay(T_right, cam);
  o.hud = &hud;
  ASSERT_TRUE(o.cue.active);
  cpu_out_.allocate(800, 300);
  gl_out_.allocate(800, 300);
  for (int e = 0; e < 2; ++e) {
    const CompositeRequest req = request(e ? T_right : T_left, {400 * e, 0, 400, 300});
    cpu_.draw(req, cpu_out_);
    gl_->draw(req, gl_out_);
  }
  const ImageRgba8 gl_before = gl_out_;
  cpu_.draw_overlay(o, {400, 0, 400, 300}, cpu_out_);
  gl_->draw_overlay(o, {400, 0, 400, 300}, gl_out_);
  int changed_right = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 400; x < 800; ++x)
      changed_right +=
          !std::equal(gl_out_.pixel(x, y), gl_out_.pixel(x, y) + 4, gl_before.pixel(x, y));
  EXPECT_GT(changed_right, 400 * 20);  // at least the whole strip
  // HUD at the right eye's top-left in GL too: its first pixel is darkened.
  EXPECT_LT(gl_out_.pixel(401, 1)[0], 30);
  EXPECT_EQ(gl_out_.pixel(399, 1)[0], 40);
  expect_lines_match(o, 40);
}

}  // namespace
}  // namespace hd::render
