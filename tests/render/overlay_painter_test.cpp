// The CPU overlay painter against closed forms: where the ghost frustum's corners land, where a
// frustum edge crossing the eye's near plane ends, that nothing is written outside the viewport
// and that the HUD strip blends only inside its strip.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>

#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"
#include "render/overlay/overlay_geometry.h"
#include "render/overlay/overlay_painter.h"

namespace hd::render {
namespace {

using core::Pinhole;
using core::Pose;

Pinhole pinhole(double f, double cx, double cy, int w, int h) {
  Pinhole k;
  k.fx = k.fy = f;
  k.cx = cx;
  k.cy = cy;
  k.width = w;
  k.height = h;
  return k;
}

Pose yaw_pitch_roll(double yaw_deg, double pitch_deg, double roll_deg, Eigen::Vector3d t) {
  const double k = std::numbers::pi / 180.0;
  return {(Eigen::AngleAxisd(yaw_deg * k, Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(pitch_deg * k, Eigen::Vector3d::UnitX()) *
           Eigen::AngleAxisd(roll_deg * k, Eigen::Vector3d::UnitZ()))
              .toRotationMatrix(),
          t};
}

void fill(ImageRgba8& img, uint8_t r, uint8_t g, uint8_t b) {
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      uint8_t* p = img.pixel(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    }
}

bool has_rgb(const ImageRgba8& img, int x, int y, const std::array<uint8_t, 3>& c) {
  const uint8_t* p = img.pixel(x, y);
  return p[0] == c[0] && p[1] == c[1] && p[2] == c[2];
}

// Distance from point q to the pixel square [x, x+1] x [y, y+1].
double distance_to_pixel(const Eigen::Vector2d& q, int x, int y) {
  const double dx = std::max({x - q.x(), 0.0, q.x() - (x + 1)});
  const double dy = std::max({y - q.y(), 0.0, q.y() - (y + 1)});
  return std::hypot(dx, dy);
}

double distance_to_segment(const Eigen::Vector2d& q, const Eigen::Vector2d& a,
                           const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (a + t * d - q).norm();
}

// The corner (u, v) of camera (k, T) on its plane z_c = d, written out independently of
// Pinhole::ray and guidance_cue.cpp.
Eigen::Vector3d corner_world(const Pinhole& k, const Pose& T, double d, double u, double v) {
  const Eigen::Vector3d cam(d * (u - k.cx) / k.fx, d * (v - k.cy) / k.fy, d);
  return T.R * cam + T.t;
}

struct Fixture {
  Pinhole eye = pinhole(400.0, 320.0, 240.0, 640, 480);
  Pose T_world_eye = Pose::identity();
  Pinhole cam = pinhole(300.0, 160.0, 120.0, 320, 240);
  Pose T_world_cam = yaw_pitch_roll(-8.0, 5.0, 3.0, {0.25, -0.1, 0.4});
  double d_m = 1.5;

  Overlay overlay() const {
    const GuidanceCamera gc{cam, T_world_cam, d_m};
    Overlay o;
    o.cue = guidance_toward_nearest(eye, T_world_eye, std::span(&gc, 1));
    o.eye = eye;
    o.T_world_eye = T_world_eye;
    o.near_m = 0.05;
    return o;
  }
};

TEST(OverlayPainter, FrustumCornersProjectWherePinholeSays) {
  Fixture f;
  const Overlay o = f.overlay();
  ASSERT_TRUE(o.cue.active);
  const Viewport vp{0, 0, 640, 480};
  OverlaySegments segs;
  overlay_geometry(o, vp, segs);
  ASSERT_EQ(segs.frustum_count, 8);  // camera in front of the eye: every edge is visible

  const double uv[4][2] = {{0, 0}, {320, 0}, {320, 240}, {0, 240}};
  ImageRgba8 img;
  img.allocate(640, 480);
  fill(img, 10, 20, 30);
  Overlay frustum_only = o;
  frustum_only.cue.direction_px.setZero();  // no arrow: only the frustum is painted
  paint_overlay(frustum_only, vp, img);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d X = corner_world(f.cam, f.T_world_cam, f.d_m, uv[k][0], uv[k][1]);
    const Eigen::Vector2d q = f.eye.project(f.T_world_eye.to_camera(X));
    ASSERT_TRUE(q.x() > 1 && q.y() > 1 && q.x() < 639 && q.y() < 479) << q.transpose();
    // The centre-to-corner edge k ends exactly there.
    EXPECT_NEAR((segs.segment[static_cast<std::size_t>(k)].b - q).norm(), 0.0, 1e-9) << k;
    // And a painted pixel lies within 0.5 px of it.
    double best = std::numeric_limits<double>::infinity();
    for (int y = 0; y < 480; ++y)
      for (int x = 0; x < 640; ++x)
        if (has_rgb(img, x, y, o.frustum_rgb)) best = std::min(best, distance_to_pixel(q, x, y));
    EXPECT_LE(best, 0.5) << "corner " << k << " at " << q.transpose();
  }
  // The centre projects where the pinhole says too (edges 0..3 start there).
  const Eigen::Vector2d c = f.eye.project(f.T_world_eye.to_camera(f.T_world_cam.t));
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR((segs.segment[static_cast<std::size_t>(k)].a - c).norm(), 0.0, 1e-9);

  // Every painted pixel is on one of the 8 edges (within the pixel's half-diagonal), and each
  // edge's midpoint pixel is painted.
  int painted = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) {
      if (!has_rgb(img, x, y, o.frustum_rgb)) continue;
      ++painted;
      double dmin = 1e9;
      for (int i = 0; i < 8; ++i)
        dmin = std::min(dmin, distance_to_segment({x + 0.5, y + 0.5},
                                                  segs.segment[static_cast<std::size_t>(i)].a,
                                                  segs.segment[static_cast<std::size_t>(i)].b));
      EXPECT_LE(dmin, 0.7072) << x << "," << y;
    }
  EXPECT_GT(painted, 200);
  for (int i = 0; i < 8; ++i) {
    const OverlaySegment& s = segs.segment[static_cast<std::size_t>(i)];
    const Eigen::Vector2d m = 0.5 * (s.a + s.b);
    bool near_mid = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int x = static_cast<int>(std::floor(m.x())) + dx;
        const int y = static_cast<int>(std::floor(m.y())) + dy;
        near_mid |= has_rgb(img, x, y, o.frustum_rgb) && distance_to_pixel(m, x, y) <= 0.5;
      }
    EXPECT_TRUE(near_mid) << "edge " << i;
  }
}

// Camera centre 1 m behind the eye (eye f = 100, principal point (320.5, 240.5)), rolled 45
// degrees, its image corner (W, H) on the optical axis so that it lands at eye point (0.1, 0, 1):
// the edge centre -> corner runs along eye row 240 and crosses the near plane z = 0.05 at
// (0.1, 0, 0.05), u = 100 * 0.1 / 0.05 + 320.5 = 520.5; the corner is at u = 100 * 0.1 / 1 +
// 320.5 = 330.5. A painter projecting the point behind the eye would draw toward
// u = 100 * 0.1 / (-1) + 320.5 = 310.5 instead. The roll keeps every other edge above row 240.
TEST(OverlayPainter, EdgeCrossingTheNearPlaneEndsWhereItCrossesIt) {
  const Pinhole eye = pinhole(100.0, 320.5, 240.5, 640, 480);
  const Pinhole cam = pinhole(200.0, 320.0, 240.0, 320, 240);
  const Pose T_world_cam = yaw_pitch_roll(0.0, 0.0, 45.0, {0.1, 0.0, -1.0});
  const GuidanceCamera gc{cam, T_world_cam, 2.0};
  Overlay o;
  o.cue = guidance_toward_nearest(eye, Pose::identity(), std::span(&gc, 1));
  ASSERT_TRUE(o.cue.active);
  ASSERT_FALSE(o.cue.target_in_front);
  ASSERT_NEAR((o.cue.frustum_world[3] - Eigen::Vector3d(0.1, 0.0, 1.0)).norm(), 0.0, 1e-12);
  o.cue.direction_px.setZero();  // no arrow over row 240
  o.eye = eye;
  o.T_world_eye = Pose::identity();
  o.near_m = 0.05;

  // The clip itself, closed form.
  Eigen::Vector3d a = T_world_cam.t, b(0.1, 0.0, 1.0);
  ASSERT_TRUE(clip_to_near_plane(a, b, 0.05));
  EXPECT_NEAR((a - Eigen::Vector3d(0.1, 0.0, 0.05)).norm(), 0.0, 1e-12);
  EXPECT_EQ(b, Eigen::Vector3d(0.1, 0.0, 1.0));

  const Viewport vp{0, 0, 640, 480};
  OverlaySegments segs;
  overlay_geometry(o, vp, segs);
  // Edge 2 (centre -> corner 3 = image corner (W, H)) runs from the crossing to the corner.
  const OverlaySegment* found = nullptr;
  for (int i = 0; i < segs.frustum_count; ++i)
    if (segs.segment[static_cast<std::size_t>(i)].edge == 2)
      found = &segs.segment[static_cast<std::size_t>(i)];
  ASSERT_NE(found, nullptr);
  const OverlaySegment& e = *found;
  EXPECT_NEAR((e.a - Eigen::Vector2d(520.5, 240.5)).norm(), 0.0, 1e-9) << e.a.transpose();
  EXPECT_NEAR((e.b - Eigen::Vector2d(330.5, 240.5)).norm(), 0.0, 1e-9) << e.b.transpose();

  ImageRgba8 img;
  img.allocate(640, 480);
  fill(img, 0, 0, 0);
  paint_overlay(o, vp, img);
  // Row 240: pixel centres 330.5 .. 519.5 lie on the clipped edge; nothing on the wrapped side
  // (310..329) nor past the crossing.
  for (int x = 330; x <= 519; ++x) EXPECT_TRUE(has_rgb(img, x, 240, o.frustum_rgb)) << x;
  for (int x = 290; x <= 329; ++x) EXPECT_FALSE(has_rgb(img, x, 240, o.frustum_rgb)) << x;
  for (int x = 521; x < 640; ++x) EXPECT_FALSE(has_rgb(img, x, 240, o.frustum_rgb)) << x;
}

TEST(OverlayGeometry, ClipToNearPlaneCases) {
  Eigen::Vector3d a(0, 0, -1), b(0, 0, -0.5);
  EXPECT_FALSE(clip_to_near_plane(a, b, 0.1));  // entirely behind
  a = {1, 2, 3}, b = {4, 5, 6};
  EXPECT_TRUE(clip_to_near_plane(a, b, 0.1));  // entirely in front: unchanged
  EXPECT_EQ(a, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(b, Eigen::Vector3d(4, 5, 6));
  a = {2, 0, 1}, b = {0, 2, -1};  // crosses z = 0.5 at t = 0.25: (1.5, 0.5, 0.5)
  EXPECT_TRUE(clip_to_near_plane(a, b, 0.5));
  EXPECT_EQ(a, Eigen::Vector3d(2, 0, 1));
  EXPECT_NEAR((b - Eigen::Vector3d(1.5, 0.5, 0.5)).norm(), 0.0, 1e-15);
  a = {0, 0, std::nan("")}, b = {0, 0, 1};
  EXPECT_FALSE(clip_to_near_plane(a, b, 0.1));
}

// A frustum edge from far behind the eye to a point in view, with a tiny near plane: the near
// crossing projects ~1e12 px away. The side-plane clip must end the edge on the image border
// exactly where the line through the two points leaves it (closed form in the image), not lose
// it to rounding. Eye f = 500, principal point (320, 240); the edge runs in the plane y = 0 from
// (-1, 0, -1) to (0.2, 0, 1): it crosses z = 1e-9 at x = -0.4, u = 500 * -0.4 / 1e-9 + 320,
// i.e. it leaves the image on the left border u = -1 (clip margin) along row v = 240.
TEST(OverlayGeometry, TinyNearPlaneEdgeEndsOnTheImageBorder) {
  Overlay o;
  o.cue.active = true;
  o.eye = pinhole(500.0, 320.0, 240.0, 640, 480);
  o.near_m = 1e-9;
  o.cue.frustum_world = {Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(0.2, 0, 1),
                         Eigen::Vector3d(0.2, 0, 1), Eigen::Vector3d(0.2, 0, 1),
                         Eigen::Vector3d(0.2, 0, 1)};
  OverlaySegments segs;
  overlay_geometry(o, {0, 0, 640, 480}, segs);
  ASSERT_GE(segs.frustum_count, 1);
  const OverlaySegment& s = segs.segment[0];
  ASSERT_EQ(s.edge, 0);
  // From the left border (viewport clip at u = 0) to the point's projection u = 500*0.2 + 320.
  EXPECT_NEAR((s.a - Eigen::Vector2d(0.0, 240.0)).norm(), 0.0, 1e-6) << s.a.transpose();
  EXPECT_NEAR((s.b - Eigen::Vector2d(420.0, 240.0)).norm(), 0.0, 1e-9) << s.b.transpose();
}

TEST(OverlayGeometry, ClipToRectCases) {
  Eigen::Vector2d a(-10, 5), b(30, 5);  // horizontal through [0, 20] x [0, 10]
  ASSERT_TRUE(clip_to_rect(a, b, 0, 0, 20, 10));
  EXPECT_NEAR((a - Eigen::Vector2d(0, 5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((b - Eigen::Vector2d(20, 5)).norm(), 0.0, 1e-12);
  a = {-5, -5}, b = {25, 25};  // diagonal y = x: enters at (0, 0), leaves at (10, 10)
  ASSERT_TRUE(clip_to_rect(a, b, 0, 0, 20, 10));
  EXPECT_NEAR((a - Eigen::Vector2d(0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((b - Eigen::Vector2d(10, 10)).norm(), 0.0, 1e-12);
  a = {-5, 11}, b = {25, 11};  // above the rectangle
  EXPECT_FALSE(clip_to_rect(a, b, 0, 0, 20, 10));
  a = {1e6, 5}, b = {-1e6, 5};
  ASSERT_TRUE(clip_to_rect(a, b, 0, 0, 20, 10));
  EXPECT_NEAR(std::abs(a.x() - b.x()), 20.0, 1e-9);
}

TEST(OverlayPainter, ArrowPointsAlongTheCueDirectionFromTheViewportCentre) {
  Overlay o;
  o.cue.active = true;
  o.cue.direction_px = {0.0, -1.0};  // up
  o.eye = pinhole(300.0, 150.0, 100.0, 300, 200);
  // A frustum entirely behind the eye: only the arrow shows.
  for (auto& p : o.cue.frustum_world) p = {0.0, 0.0, -5.0};
  ImageRgba8 img;
  img.allocate(500, 300);
  fill(img, 0, 0, 0);
  const Viewport vp{200, 50, 300, 200};
  paint_overlay(o, vp, img);
  // Shaft: from (350, 150) up by 200/3 px, 2 * 1 + 1 px wide (r = max(1, 200/150) = 1).
  for (int y = 90; y < 150; ++y) {
    EXPECT_TRUE(has_rgb(img, 349, y, o.arrow_rgb)) << y;
    EXPECT_TRUE(has_rgb(img, 350, y, o.arrow_rgb)) << y;
    EXPECT_TRUE(has_rgb(img, 351, y, o.arrow_rgb)) << y;
  }
  // Below the centre nothing (the arrow goes up), and no frustum colour anywhere.
  for (int y = 152; y < 250; ++y) EXPECT_FALSE(has_rgb(img, 350, y, o.arrow_rgb)) << y;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 500; ++x) ASSERT_FALSE(has_rgb(img, x, y, o.frustum_rgb));
}

TEST(OverlayPainter, InactiveCueAndNoHudDrawNothing) {
  Fixture f;
  Overlay o = f.overlay();
  o.cue.active = false;
  ImageRgba8 img;
  img.allocate(640, 480);
  fill(img, 1, 2, 3);
  const std::vector<uint8_t> before = img.data;
  paint_overlay(o, {0, 0, 640, 480}, img);
  EXPECT_EQ(img.data, before);
}

TEST(OverlayPainter, HudBlendsOnlyInsideItsStrip) {
  HudStrip hud(200, 20);
  EXPECT_TRUE(hud.empty());
  ASSERT_TRUE(hud.set_text("frame 41 MTP 12.5 ms"));
  EXPECT_FALSE(hud.set_text("frame 41 MTP 12.5 ms"));  // same text: no re-render
  EXPECT_EQ(hud.text(), "frame 41 MTP 12.5 ms");
  Overlay o;
  o.hud = &hud;
  ImageRgba8 img;
  img.allocate(400, 300);
  fill(img, 200, 100, 50);
  const Viewport vp{50, 30, 300, 200};
  paint_overlay(o, vp, img);
  int changed = 0, bright = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) {
      const uint8_t* p = img.pixel(x, y);
      const bool same = p[0] == 200 && p[1] == 100 && p[2] == 50 && p[3] == 255;
      const bool in_strip = x >= 50 && x < 250 && y >= 30 && y < 50;
      if (!in_strip) {
        ASSERT_TRUE(same) << x << "," << y;
        continue;
      }
      changed += !same;
      bright += p[0] > 200;
      EXPECT_EQ(p[3], 255);
    }
  EXPECT_EQ(changed, 200 * 20);  // the translucent background darkens the whole strip
  EXPECT_GT(bright, 30);         // and the glyphs are lighter than the picture
  // A background pixel (top-left corner of the strip): (a * 0 + (255 - a) * o + 127) / 255.
  const int a = HudStrip::kBackgroundAlpha;
  const uint8_t* p = img.pixel(50, 30);
  EXPECT_EQ(p[0], ((255 - a) * 200 + 127) / 255);
  EXPECT_EQ(p[1], ((255 - a) * 100 + 127) / 255);
  EXPECT_EQ(p[2], ((255 - a) * 50 + 127) / 255);

  // A viewport narrower than the strip clips the strip.
  fill(img, 200, 100, 50);
  paint_overlay(o, {0, 0, 120, 10}, img);
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x)
      if (x >= 120 || y >= 10) {
        ASSERT_EQ(img.pixel(x, y)[0], 200) << x << "," << y;
      }

  const uint64_t r = hud.revision();
  ASSERT_TRUE(hud.set_text(""));
  EXPECT_NE(hud.revision(), r);
  EXPECT_TRUE(hud.empty());
  EXPECT_TRUE(o.empty());  // nothing left to draw
}

// Random cameras, eyes and viewports: the painter never writes outside its viewport, never
// crashes, and every frustum segment it returns lies inside the viewport.
RC_GTEST_PROP(OverlayPainter, NeverWritesOutsideTheViewport, ()) {
  const auto angle = [] { return *rc::gen::inRange(-180, 181); };
  const auto pos_cm = [] { return *rc::gen::inRange(-300, 301) / 100.0; };
  const Pose T_cam =
      yaw_pitch_roll(angle(), angle() / 2.0, angle(), {pos_cm(), pos_cm(), pos_cm()});
  const Pose T_eye =
      yaw_pitch_roll(angle(), angle() / 2.0, angle(), {pos_cm(), pos_cm(), pos_cm()});
  const int vw = *rc::gen::inRange(16, 200), vh = *rc::gen::inRange(16, 160);
  const int vx = *rc::gen::inRange(0, 60), vy = *rc::gen::inRange(0, 40);
  const double f_eye = *rc::gen::inRange(20, 2000);
  const Pinhole eye = pinhole(f_eye, vw / 2.0, vh / 2.0, vw, vh);
  const Pinhole cam = pinhole(*rc::gen::inRange(50, 1000), 80, 60, 160, 120);
  const GuidanceCamera gc{cam, T_cam, *rc::gen::inRange(1, 500) / 100.0};
  Overlay o;
  o.cue = guidance_toward_nearest(eye, T_eye, std::span(&gc, 1));
  o.eye = eye;
  o.T_world_eye = T_eye;
  o.near_m = *rc::gen::inRange(1, 100) / 1000.0;
  const Viewport vp{vx, vy, vw, vh};
  OverlaySegments segs;
  overlay_geometry(o, vp, segs);
  for (int i = 0; i < segs.count; ++i)
    for (const Eigen::Vector2d& p : {segs.segment[static_cast<std::size_t>(i)].a,
                                     segs.segment[static_cast<std::size_t>(i)].b}) {
      RC_ASSERT(p.x() >= vx - 1e-9 && p.x() <= vx + vw + 1e-9);
      RC_ASSERT(p.y() >= vy - 1e-9 && p.y() <= vy + vh + 1e-9);
    }
  ImageRgba8 img;
  img.allocate(vx + vw + 20, vy + vh + 20);
  fill(img, 7, 7, 7);
  paint_overlay(o, vp, img);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      if (x >= vx && x < vx + vw && y >= vy && y < vy + vh) continue;
      const uint8_t* p = img.pixel(x, y);
      RC_ASSERT(p[0] == 7 && p[1] == 7 && p[2] == 7);
    }
}

}  // namespace
}  // namespace hd::render
