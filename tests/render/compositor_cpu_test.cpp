// The CPU reference compositor against independent expectations: closed forms, an analytic
// ray/plane mapping, hand-computed weights and marks, and a counting allocator.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <numbers>

#include "render/compositor/cpu_compositor.h"
#include "render/compositor/look_pose.h"

// Counting allocator: every operator new in this binary passes through here. GCC 12 flags the
// malloc/free pairing inside replaced operators as a mismatch; it is the standard replacement.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace {

using hd::core::MarkingStyle;
using hd::core::Pinhole;
using hd::core::Pose;
using hd::core::TransitionMode;
using hd::core::Variant;
using hd::drivers::Frame;
using hd::render::CompositeRequest;
using hd::render::CpuCompositor;
using hd::render::ImageRgba8;
using hd::render::look_pose;
using hd::render::SyntheticScene;
using hd::render::TexturedMesh;

Pinhole pinhole(double f, int w, int h) {
  return Pinhole::centred(f, w, h);
}

// A frame whose every pixel has a distinct, position-coded colour.
Frame coded_frame(int w, int h) {
  Frame f;
  f.allocate_rgba(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = f.data.data() + y * f.stride_bytes + 4 * x;
      p[0] = static_cast<uint8_t>(x * 7 + y);
      p[1] = static_cast<uint8_t>(y * 5 + x * 3);
      p[2] = static_cast<uint8_t>(x ^ y);
      p[3] = 255;
    }
  }
  return f;
}

Frame uniform_frame(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  Frame f;
  f.allocate_rgba(w, h);
  for (std::size_t i = 0; i < f.data.size(); i += 4) {
    f.data[i] = r;
    f.data[i + 1] = g;
    f.data[i + 2] = b;
    f.data[i + 3] = 255;
  }
  return f;
}

CompositeRequest video_request(const Pinhole& eye, const Frame* frame, const Pinhole& real) {
  CompositeRequest r;
  r.eye = eye;
  r.video = frame;
  r.real = real;
  r.d_m = 2.0;
  r.has_region = true;
  r.region = {0, 0, static_cast<double>(real.width), static_cast<double>(real.height)};
  r.transition = {Variant::kVideo, 1.0, 0.0};
  r.mode = TransitionMode::kGlobalBlend;
  r.marking.style = MarkingStyle::kNone;
  r.viewport = {0, 0, eye.width, eye.height};
  return r;
}

// An axis-aligned square facing the eye at depth z, corners at (x0,y0)..(x1,y1), two triangles
// split along the (x0,y0)-(x1,y1) diagonal, with a texture of 2x2 blocks of four colours.
TexturedMesh facing_quad(double x0, double y0, double x1, double y1, double z) {
  TexturedMesh m;
  m.positions_m = {{float(x0), float(y0), float(z)},
                   {float(x1), float(y0), float(z)},
                   {float(x1), float(y1), float(z)},
                   {float(x0), float(y1), float(z)}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(4, 4);
  const uint8_t colours[4][3] = {{250, 0, 0}, {0, 250, 0}, {0, 0, 250}, {250, 250, 0}};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const uint8_t* c = colours[(y / 2) * 2 + (x / 2)];
      uint8_t* p = m.texture.pixel(x, y);
      p[0] = c[0];
      p[1] = c[1];
      p[2] = c[2];
      p[3] = 255;
    }
  }
  return m;
}

bool same_rgb(const uint8_t* p, uint8_t r, uint8_t g, uint8_t b) {
  return p[0] == r && p[1] == g && p[2] == b;
}

TEST(CpuCompositor, IdenticalCamerasWithFullVideoWeightReproduceTheFrameExactly) {
  const Pinhole cam = pinhole(300.0, 160, 120);
  const Frame frame = coded_frame(160, 120);
  for (int threads : {1, 2}) {
    for (auto sampling :
         {hd::render::VideoSampling::kBilinear, hd::render::VideoSampling::kNearest}) {
      CpuCompositor comp(threads);
      ImageRgba8 out;
      out.allocate(160, 120);
      CompositeRequest req = video_request(cam, &frame, cam);
      req.sampling = sampling;
      comp.draw(req, out);
      int mismatches = 0;
      for (int y = 0; y < 120; ++y) {
        for (int x = 0; x < 160; ++x) {
          const uint8_t* o = out.pixel(x, y);
          const uint8_t* f = frame.data.data() + y * frame.stride_bytes + 4 * x;
          mismatches += (o[0] != f[0] || o[1] != f[1] || o[2] != f[2] || o[3] != 255) ? 1 : 0;
        }
      }
      EXPECT_EQ(mismatches, 0) << "threads " << threads;
    }
  }
}

TEST(CpuCompositor, FacingQuadCoversExactlyItsProjectionWithItsTextureColours) {
  // f = 400, 640x480, quad 1 m x 1 m at 2 m: projects to u in [220, 420], v in [140, 340].
  const Pinhole eye = pinhole(400.0, 640, 480);
  SyntheticScene scene;
  scene.background_rgb = {10, 20, 30};
  scene.meshes.push_back(facing_quad(-0.5, -0.5, 0.5, 0.5, 2.0));
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(640, 480);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.marking.style = MarkingStyle::kNone;
  req.viewport = {0, 0, 640, 480};
  comp.draw(req, out);
  int covered = 0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) covered += same_rgb(out.pixel(x, y), 10, 20, 30) ? 0 : 1;
  }
  EXPECT_EQ(covered, 200 * 200);
  EXPECT_TRUE(same_rgb(out.pixel(220, 140), 250, 0, 0));    // top-left block
  EXPECT_TRUE(same_rgb(out.pixel(419, 140), 0, 250, 0));    // top-right
  EXPECT_TRUE(same_rgb(out.pixel(220, 339), 0, 0, 250));    // bottom-left
  EXPECT_TRUE(same_rgb(out.pixel(419, 339), 250, 250, 0));  // bottom-right
  EXPECT_TRUE(same_rgb(out.pixel(219, 200), 10, 20, 30));
  EXPECT_TRUE(same_rgb(out.pixel(420, 200), 10, 20, 30));
  EXPECT_EQ(comp.stats().frames_drawn, 1u);
}

TEST(CpuCompositor, TopLeftRuleCoversEachCentreOnSharedAndOuterEdgesExactlyOnce) {
  // Corners at half-integer pixels (u = 220.5 .. 420.5): every edge, including the shared
  // diagonal, passes through pixel centres. Top/left edges own them: 200 x 200 pixels, no holes.
  const Pinhole eye = pinhole(200.0, 640, 480);
  SyntheticScene scene;
  scene.background_rgb = {10, 20, 30};
  const double a = (220.5 - 320.0) / 100.0, b = (420.5 - 320.0) / 100.0;
  const double c = (140.5 - 240.0) / 100.0, d = (340.5 - 240.0) / 100.0;
  scene.meshes.push_back(facing_quad(a, c, b, d, 2.0));
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(640, 480);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.marking.style = MarkingStyle::kNone;
  req.viewport = {0, 0, 640, 480};
  comp.draw(req, out);
  int covered = 0, holes = 0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      const bool drawn = !same_rgb(out.pixel(x, y), 10, 20, 30);
      covered += drawn ? 1 : 0;
      const bool expect = x >= 220 && x < 420 && y >= 140 && y < 340;
      holes += (expect && !drawn) ? 1 : 0;
    }
  }
  EXPECT_EQ(covered, 200 * 200);
  EXPECT_EQ(holes, 0);
}

TEST(CpuCompositor, TiltedQuadIsInterpolatedPerspectiveCorrectly) {
  // A floor strip from z = 1 m to z = 3 m at y = 0.5 m below the eye; texture t runs with z, its
  // rows hold the value of their index (t * 256). The world midpoint z = 2 m (t = 0.5) projects
  // to v = cy + f * 0.5 / 2; affine interpolation would put t = 0.5 at the screen midpoint.
  const Pinhole eye = pinhole(200.0, 320, 240);
  TexturedMesh m;
  m.positions_m = {{-1, 0.5f, 1}, {1, 0.5f, 1}, {1, 0.5f, 3}, {-1, 0.5f, 3}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(1, 256);
  for (int j = 0; j < 256; ++j) {
    uint8_t* p = m.texture.pixel(0, j);
    p[0] = p[1] = p[2] = static_cast<uint8_t>(j);
    p[3] = 255;
  }
  SyntheticScene scene;
  scene.meshes.push_back(m);
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(320, 240);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.marking.style = MarkingStyle::kNone;
  req.viewport = {0, 0, 320, 240};
  comp.draw(req, out);
  // Rows: z = f * 0.5 / (v - cy). Check several rows against t = (z - 1) / 2 exactly.
  for (int row : {150, 160, 170, 180, 200, 220}) {
    const double v = row + 0.5;
    const double z = 200.0 * 0.5 / (v - 120.0);
    if (z < 1.0 || z > 3.0) continue;
    const double t = (z - 1.0) / 2.0;
    const double expected = std::clamp(t * 256.0 - 0.5, 0.0, 255.0);  // bilinear between rows
    EXPECT_NEAR(out.pixel(160, row)[0], expected, 1.0) << "row " << row;
  }
}

// The real pixel an eye pixel centre sees on the plane z_real = d, computed by ray casting.
bool analytic_real_pixel(const Pinhole& eye, const Pose& T_we, const Pinhole& real,
                         const Pose& T_wr, double d, double x, double y, double* u, double* v) {
  const Eigen::Vector3d dir_eye((x + 0.5 - eye.cx) / eye.fx, (y + 0.5 - eye.cy) / eye.fy, 1.0);
  const Eigen::Vector3d o_r = T_wr.to_camera(T_we.t);
  const Eigen::Vector3d dir_r = T_wr.R.transpose() * (T_we.R * dir_eye);
  if (std::abs(dir_r.z()) < 1e-12) return false;
  const double s = (d - o_r.z()) / dir_r.z();
  if (s <= 0.05) return false;  // behind the eye (or before its near plane)
  const Eigen::Vector3d X = o_r + s * dir_r;
  *u = real.fx * X.x() / X.z() + real.cx;
  *v = real.fy * X.y() / X.z() + real.cy;
  return true;
}

TEST(CpuCompositor, WarpOfACheckerFrameFollowsTheAnalyticRayPlaneMapping) {
  const Pinhole real = pinhole(500.0, 400, 300);
  const Pinhole eye = pinhole(350.0, 320, 240);
  const Pose T_wr = Pose::identity();
  const Pose T_we = look_pose(10.0, 0.0, {0.12, -0.05, 0.3});
  const int cell = 20;
  Frame frame;
  frame.allocate_rgba(400, 300);
  for (int y = 0; y < 300; ++y) {
    for (int x = 0; x < 400; ++x) {
      uint8_t* p = frame.data.data() + y * frame.stride_bytes + 4 * x;
      const bool odd = ((x / cell) + (y / cell)) & 1;
      p[0] = odd ? 230 : 20;
      p[1] = odd ? 40 : 210;
      p[2] = 90;
      p[3] = 255;
    }
  }
  SyntheticScene scene;
  scene.background_rgb = {1, 2, 3};
  CpuCompositor comp(2);
  ImageRgba8 out;
  out.allocate(320, 240);
  CompositeRequest req = video_request(eye, &frame, real);
  req.scene = &scene;
  req.T_world_eye = T_we;
  req.T_world_real = T_wr;
  comp.draw(req, out);
  int checked = 0, wrong = 0, outside = 0;
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      double u = 0, v = 0;
      const uint8_t* o = out.pixel(x, y);
      const bool hit = analytic_real_pixel(eye, T_we, real, T_wr, 2.0, x, y, &u, &v);
      if (!hit || u < -0.01 || v < -0.01 || u > 400.01 || v > 300.01) {
        ++outside;
        wrong += same_rgb(o, 1, 2, 3) ? 0 : 1;
        continue;
      }
      // Away from cell borders (and the frame border) bilinear sampling is exactly the cell.
      const double fu = std::fmod(u, cell), fv = std::fmod(v, cell);
      if (fu < 1.0 || fu > cell - 1.0 || fv < 1.0 || fv > cell - 1.0) continue;
      if (u < 1.0 || v < 1.0 || u > 399.0 || v > 299.0) continue;
      const bool odd = ((int(u) / cell) + (int(v) / cell)) & 1;
      ++checked;
      wrong += same_rgb(o, odd ? 230 : 20, odd ? 40 : 210, 90) ? 0 : 1;
    }
  }
  EXPECT_GT(checked, 30000);
  EXPECT_GT(outside, 1000);  // the turned eye sees past the frame's edge
  EXPECT_EQ(wrong, 0);
}

// The paper's w2 with DESIGN 6's corner and the DESIGN 7 continuity rule, written out here.
double expected_weight(double w_video, double u, double v, double W, double H) {
  const double strength = std::min(1.0, 2.0 * w_video);
  const double kappa = std::min(1.0, 2.0 * (1.0 - w_video));
  if (kappa == 0.0) return strength;
  const double xp = std::abs(1.0 - 2.0 * u / W), yp = std::abs(1.0 - 2.0 * v / H);
  const double in = 1.0 - kappa;
  double w1;
  if (xp <= in && yp <= in)
    w1 = 1.0;
  else if (yp <= in)
    w1 = (1.0 - xp) / kappa;
  else if (xp <= in)
    w1 = (1.0 - yp) / kappa;
  else
    w1 = 1.0 - std::sqrt((xp - in) * (xp - in) + (yp - in) * (yp - in)) / kappa;
  w1 = std::clamp(w1, 0.0, 1.0);
  return strength * (std::sin((w1 - 0.5) * std::numbers::pi) + 1.0) / 2.0;
}

TEST(CpuCompositor, PerPixelWeightsFollowTheSinusoidalBorderAtTheRealImagePosition) {
  const Pinhole cam = pinhole(300.0, 200, 160);
  const Frame white = uniform_frame(200, 160, 255, 255, 255);
  SyntheticScene scene;
  scene.background_rgb = {0, 0, 0};
  for (double w_video : {1.0, 0.8, 0.6, 0.3}) {
    CpuCompositor comp;
    ImageRgba8 out;
    out.allocate(200, 160);
    CompositeRequest req = video_request(cam, &white, cam);
    req.scene = &scene;
    req.mode = TransitionMode::kPerPixel;
    req.transition = {Variant::kHybrid, w_video, 1.0 - w_video};
    comp.draw(req, out);
    double max_err = 0.0;
    for (int y = 0; y < 160; ++y) {
      for (int x = 0; x < 200; ++x) {
        const double expect = 255.0 * expected_weight(w_video, x + 0.5, y + 0.5, 200, 160);
        max_err = std::max(max_err, std::abs(out.pixel(x, y)[0] - expect));
      }
    }
    EXPECT_LE(max_err, 0.5 + 1e-3) << "w_video " << w_video;
  }
  // One point by hand: w_video = 0.8 -> strength 1, kappa' = 0.4, inner 0.6. At u = 15.5,
  // x' = 0.845 -> w'2 = 0.155 / 0.4 = 0.3875 -> w2 = (sin(-0.1125 pi) + 1) / 2 = 0.32717.
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(200, 160);
  CompositeRequest req = video_request(cam, &white, cam);
  req.scene = &scene;
  req.mode = TransitionMode::kPerPixel;
  req.transition = {Variant::kHybrid, 0.8, 0.2};
  comp.draw(req, out);
  EXPECT_EQ(out.pixel(15, 80)[0], 83);    // 255 * 0.32717 = 83.43
  EXPECT_EQ(out.pixel(100, 80)[0], 255);  // centre: full video
}

TEST(CpuCompositor, GlobalBlendMixesVideoAndModelByWVideo) {
  const Pinhole cam = pinhole(300.0, 64, 48);
  const Frame frame = uniform_frame(64, 48, 200, 100, 0);
  SyntheticScene scene;
  scene.background_rgb = {0, 100, 200};
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(64, 48);
  CompositeRequest req = video_request(cam, &frame, cam);
  req.scene = &scene;
  req.transition = {Variant::kHybrid, 0.25, 0.75};
  comp.draw(req, out);
  EXPECT_TRUE(same_rgb(out.pixel(10, 10), 50, 100, 150));
  EXPECT_TRUE(same_rgb(out.pixel(63, 47), 50, 100, 150));
}

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

TEST(CpuCompositor, TriangleCrossingTheNearPlaneIsClippedNotDropped) {
  // A wall in the plane x = 0.3 running from behind the eye (z = -1) to z = 5.
  const Pinhole eye = pinhole(200.0, 320, 240);
  TexturedMesh m = facing_quad(0, 0, 1, 1, 1);
  m.positions_m = {{0.3f, -1, -1}, {0.3f, -1, 5}, {0.3f, 1, 5}, {0.3f, 1, -1}};
  SyntheticScene scene;
  scene.background_rgb = {0, 0, 0};
  scene.meshes.push_back(m);
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(320, 240);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.near_m = 0.1;
  req.marking.style = MarkingStyle::kNone;
  req.viewport = {0, 0, 320, 240};
  comp.draw(req, out);
  // At the image row through the centre the wall spans u from 160 + 200*0.3/5 = 172 to the
  // right edge (u -> inf as z -> 0).
  EXPECT_TRUE(same_rgb(out.pixel(170, 120), 0, 0, 0));
  EXPECT_FALSE(same_rgb(out.pixel(175, 120), 0, 0, 0));
  EXPECT_FALSE(same_rgb(out.pixel(319, 120), 0, 0, 0));
}

TEST(CpuCompositor, NearerSurfaceWinsTheDepthTestWhateverTheDrawOrder) {
  const Pinhole eye = pinhole(200.0, 160, 120);
  TexturedMesh near_q = facing_quad(-0.2, -0.2, 0.2, 0.2, 1.0);  // red block in the middle
  TexturedMesh far_q = facing_quad(-2.0, -2.0, 2.0, 2.0, 3.0);
  for (std::size_t i = 0; i < far_q.texture.data.size(); i += 4) {  // all green
    far_q.texture.data[i] = 0;
    far_q.texture.data[i + 1] = 250;
    far_q.texture.data[i + 2] = 0;
  }
  for (int order = 0; order < 2; ++order) {
    SyntheticScene scene;
    scene.meshes =
        order ? std::vector<TexturedMesh>{near_q, far_q} : std::vector<TexturedMesh>{far_q, near_q};
    CpuCompositor comp;
    ImageRgba8 out;
    out.allocate(160, 120);
    CompositeRequest req;
    req.scene = &scene;
    req.eye = eye;
    req.marking.style = MarkingStyle::kNone;
    req.viewport = {0, 0, 160, 120};
    comp.draw(req, out);
    // Inside the near quad's top-left (red) block; the far quad is all green.
    const uint8_t* p = out.pixel(50, 30);
    EXPECT_TRUE(same_rgb(p, 250, 0, 0)) << order;
    EXPECT_TRUE(same_rgb(out.pixel(150, 110), 0, 250, 0)) << order;  // only the far quad there
  }
}

TEST(CpuCompositor, TwoThreadsGiveTheSameBytesAsOne) {
  const Pinhole eye = pinhole(250.0, 300, 200);
  const Pinhole real = pinhole(400.0, 320, 240);
  const Frame frame = coded_frame(320, 240);
  SyntheticScene scene;
  scene.meshes.push_back(facing_quad(-1.0, -0.6, 0.8, 0.7, 2.5));
  ImageRgba8 a, b;
  a.allocate(300, 200);
  b.allocate(300, 200);
  CompositeRequest req = video_request(eye, &frame, real);
  req.scene = &scene;
  req.T_world_eye = look_pose(8.6, 0.0, {0.2, 0.0, 0.1});
  req.mode = TransitionMode::kPerPixel;
  req.transition = {Variant::kHybrid, 0.7, 0.3};
  req.marking.style = MarkingStyle::kChecker;
  CpuCompositor one(1), two(2);
  one.draw(req, a);
  two.draw(req, b);
  EXPECT_EQ(a.data, b.data);
}

TEST(CpuCompositor, MalformedRequestsAreRejectedAndCountedWithoutTouchingTheOutput) {
  const Pinhole cam = pinhole(100.0, 64, 48);
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(64, 48);
  CompositeRequest req;
  req.eye = cam;
  req.viewport = {10, 0, 64, 48};  // sticks out of `out`
  comp.draw(req, out);
  req.viewport = {0, 0, 64, 48};
  req.eye.fx = std::nan("");
  comp.draw(req, out);
  req.eye = cam;
  req.T_world_eye.t.x() = std::numeric_limits<double>::infinity();
  comp.draw(req, out);
  EXPECT_EQ(comp.stats().requests_rejected, 3u);
  EXPECT_EQ(comp.stats().frames_drawn, 0u);
  for (uint8_t byte : out.data) ASSERT_EQ(byte, 0);

  // A frame in the wrong format or size is ignored (synthetic only) and counted.
  Frame rgb = uniform_frame(64, 48, 255, 0, 0);
  rgb.format = hd::drivers::PixelFormat::kRgb8;
  SyntheticScene scene;
  scene.background_rgb = {7, 8, 9};
  CompositeRequest vreq = video_request(cam, &rgb, cam);
  vreq.scene = &scene;
  comp.draw(vreq, out);
  Frame short_frame = uniform_frame(64, 48, 255, 0, 0);
  short_frame.data.resize(100);
  vreq.video = &short_frame;
  comp.draw(vreq, out);
  EXPECT_EQ(comp.stats().video_frames_rejected, 2u);
  EXPECT_TRUE(same_rgb(out.pixel(30, 20), 7, 8, 9));
}

TEST(CpuCompositor, DrawingAllocatesNothingAfterTheFirstFrame) {
  const Pinhole eye = pinhole(250.0, 300, 200);
  const Pinhole real = pinhole(400.0, 320, 240);
  const Frame frame = coded_frame(320, 240);
  SyntheticScene scene;
  scene.meshes.push_back(facing_quad(-1.0, -0.6, 0.8, 0.7, 2.5));
  ImageRgba8 out;
  out.allocate(300, 200);
  CompositeRequest req = video_request(eye, &frame, real);
  req.scene = &scene;
  req.mode = TransitionMode::kPerPixel;
  CpuCompositor comp(2);
  comp.draw(req, out);  // warm-up sizes the buffers
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 20; ++i) {
    req.transition = {Variant::kHybrid, i / 20.0, 1.0 - i / 20.0};
    req.T_world_eye = look_pose(0.5 * i, 0.0, {0.01 * i, 0.0, 0.0});
    comp.draw(req, out);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(comp.stats().frames_drawn, 21u);
}

}  // namespace
