// The GL compositor against the CPU reference on Mesa's llvmpipe (run under xvfb-run with
// LIBGL_ALWAYS_SOFTWARE=1). No GL 3.3 core context is a failure, not a skip.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include "core/view_measure.h"
#include "core/view_setup.h"
#include "render/compositor/cpu_compositor.h"
#include "render/compositor/demo_scene.h"
#include "render/compositor/look_pose.h"
#include "render/gl/gl_compositor.h"
#include "support/gl_vs_cpu_test.h"

namespace {

using hd::core::MarkingStyle;
using hd::core::Pinhole;
using hd::core::Pose;
using hd::core::TransitionMode;
using hd::core::Variant;
using hd::render::CompositeRequest;
using hd::render::CpuCompositor;
using hd::render::GlCompositor;
using hd::render::ImageRgba8;
using hd::render::look_pose;

Pinhole pinhole(double f, int w, int h) {
  return Pinhole::centred(f, w, h);
}

// PSNR over RGB; also checks the picture is not trivially flat (a blank GL output would match a
// blank CPU output perfectly).
double psnr_db(const ImageRgba8& a, const ImageRgba8& b) {
  int varied = 0;
  for (int y = 1; y < a.height; ++y) {
    for (int x = 1; x < a.width; ++x) {
      varied += (a.pixel(x, y)[1] != a.pixel(x - 1, y - 1)[1]) ? 1 : 0;
    }
  }
  EXPECT_GT(varied, a.width * a.height / 20) << "reference picture is nearly flat";
  double se = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.pixel(x, y)[c]) - double(b.pixel(x, y)[c]);
        se += d * d;
      }
    }
  }
  const double mse = se / (3.0 * a.width * a.height);
  const double db = mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
  std::printf("    PSNR GL vs CPU: %.2f dB\n", db);
  return db;
}

class GlCompositorTest : public hd::render::test::GlVsCpuTest {
 protected:
  void SetUp() override {
    GlVsCpuTest::SetUp();
    if (HasFatalFailure()) return;
    scene_ = hd::render::make_demo_scene();
    hd::render::render_demo_frame(scene_, real_, T_world_real_, 25, frame_);
    frame_.sequence = ++sequence_;
  }

  CompositeRequest base_request() const {
    CompositeRequest r;
    r.scene = &scene_;
    r.eye = eye_;
    r.T_world_eye = look_pose(4.0, -3.0, {0.05, -0.02, 0.0});
    r.video = &frame_;
    r.real = real_;
    r.T_world_real = T_world_real_;
    r.d_m = 1.3;
    r.has_region = true;
    r.region = {0, 0, double(real_.width), double(real_.height)};
    r.transition = {Variant::kVideo, 1.0, 0.0};
    r.mode = TransitionMode::kAbrupt;
    r.marking.style = MarkingStyle::kNone;
    r.viewport = {0, 0, eye_.width, eye_.height};
    return r;
  }

  static inline uint64_t sequence_ = 0;
  Pinhole eye_ = pinhole(330.0, 400, 300);
  Pinhole real_ = pinhole(420.0, 480, 360);
  Pose T_world_real_ = look_pose(0.0, -5.0, {0.0, -0.1, -0.2});
  hd::render::SyntheticScene scene_;
  hd::drivers::Frame frame_;
};

TEST_F(GlCompositorTest, RunsOnLlvmpipeWithACoreContext) {
  EXPECT_NE(gl_->renderer().find("llvmpipe"), std::string::npos) << gl_->renderer();
  // Mesa reports e.g. "4.5 (Core Profile) Mesa 22.3.6": a core context of at least 3.3.
  const std::string v = gl_->version();
  int major = 0, minor = 0;
  ASSERT_EQ(std::sscanf(v.c_str(), "%d.%d", &major, &minor), 2) << v;
  EXPECT_GE(major * 10 + minor, 33) << v;
  EXPECT_NE(v.find("Core Profile"), std::string::npos) << v;
}

TEST_F(GlCompositorTest, VideoOnlyMatchesTheCpuReference) {
  CompositeRequest req = base_request();
  req.scene = nullptr;
  draw_both(req, 400, 300);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, VideoWithNearestSamplingMatchesTheCpuReference) {
  CompositeRequest req = base_request();
  req.sampling = hd::render::VideoSampling::kNearest;
  draw_both(req, 400, 300);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, SyntheticOnlyMatchesTheCpuReference) {
  CompositeRequest req = base_request();
  req.video = nullptr;
  req.transition = {Variant::kSynthetic, 0.0, 1.0};
  draw_both(req, 400, 300);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, PerPixelHybridWithDesaturationMatchesTheCpuReference) {
  CompositeRequest req = base_request();
  req.T_world_eye = look_pose(14.0, -6.0, {0.25, -0.05, 0.1});
  req.mode = TransitionMode::kPerPixel;
  req.transition = {Variant::kHybrid, 0.65, 0.35};
  req.marking.style = MarkingStyle::kDesaturate;
  draw_both(req, 400, 300);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, GlobalBlendWithCheckerMatchesTheCpuReference) {
  CompositeRequest req = base_request();
  req.T_world_eye = look_pose(-12.0, 4.0, {-0.2, 0.05, 0.3});
  req.mode = TransitionMode::kGlobalBlend;
  req.transition = {Variant::kHybrid, 0.4, 0.6};
  req.marking.style = MarkingStyle::kChecker;
  draw_both(req, 400, 300);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, FrameMarksAreIdenticalForEveryVariant) {
  for (Variant v : {Variant::kVideo, Variant::kHybrid, Variant::kSynthetic}) {
    CompositeRequest req = base_request();
    req.mode = TransitionMode::kPerPixel;
    req.transition = {v, v == Variant::kVideo ? 1.0 : v == Variant::kHybrid ? 0.6 : 0.0, 0.0};
    req.marking.style = MarkingStyle::kFrame;
    req.marking.frame_width_px = 6;
    draw_both(req, 400, 300);
    EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
    const auto& fc = req.marking.frame_colour(v);
    int frame_px = 0, equal = 0;
    for (int y = 0; y < 300; ++y) {
      for (int x = 0; x < 400; ++x) {
        if (x >= 6 && y >= 6 && x < 394 && y < 294) continue;
        ++frame_px;
        const uint8_t* g = gl_out_.pixel(x, y);
        const uint8_t* c = cpu_out_.pixel(x, y);
        equal += (g[0] == fc.r && g[1] == fc.g && g[2] == fc.b && c[0] == fc.r && c[1] == fc.g &&
                  c[2] == fc.b)
                     ? 1
                     : 0;
      }
    }
    EXPECT_EQ(equal, frame_px) << "variant " << static_cast<int>(v);
  }
}

// The model-depth view off the camera (per-pixel blend, so the border weight is in it too): the
// same pixels see video in both, and the pictures agree within 2 levels nearly everywhere (a
// texel at a depth edge may go either way in float and double).
TEST_F(GlCompositorTest, ModelDepthViewMatchesTheCpuReference) {
  CompositeRequest req = base_request();
  req.T_world_eye = look_pose(14.0, -6.0, {0.25, -0.05, 0.1});
  req.mode = TransitionMode::kPerPixel;
  req.transition = {Variant::kHybrid, 0.8, 0.2};
  req.video_view = hd::core::VideoView::kModelDepth;
  const uint64_t renders = gl_->stats().camera_depth_renders;
  draw_both(req, 400, 300);
  EXPECT_EQ(gl_->stats().camera_depth_renders, renders + 1);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
  int off = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x)
      for (int c = 0; c < 3; ++c)
        off += std::abs(cpu_out_.pixel(x, y)[c] - gl_out_.pixel(x, y)[c]) > 2;
  std::printf("    channel values more than 2 levels apart: %d of %d\n", off, 400 * 300 * 3);
  EXPECT_LE(off, 400 * 300 * 3 / 1000);
  // The plane view differs from it (the view is really switched), and a second draw of the same
  // model and camera re-uses the depth map.
  const ImageRgba8 depth_picture = gl_out_;
  req.video_view = hd::core::VideoView::kPlane;
  draw_both(req, 400, 300);
  EXPECT_LT(psnr_db(depth_picture, gl_out_), 35.0);
  req.video_view = hd::core::VideoView::kModelDepth;
  draw_both(req, 400, 300);
  EXPECT_EQ(gl_->stats().camera_depth_renders, renders + 1);
}

TEST_F(GlCompositorTest, StereoViewportsSideBySideMatchTheCpuReference) {
  cpu_out_.allocate(800, 300);
  gl_out_.allocate(800, 300);
  for (int eye = 0; eye < 2; ++eye) {
    CompositeRequest req = base_request();
    req.T_world_eye = look_pose(6.0, -2.0, {eye ? 0.032 : -0.032, 0.0, 0.05});
    req.mode = TransitionMode::kPerPixel;
    req.transition = {Variant::kHybrid, 0.8, 0.2};
    req.viewport = {eye * 400, 0, 400, 300};
    cpu_.draw(req, cpu_out_);
    gl_->draw(req, gl_out_);
  }
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, UploadsExactlyTheUpdateRegionGrownToWholePixels) {
  CompositeRequest req = base_request();
  req.region = {10.3, 20.7, 100.2, 80.9};
  const auto before = gl_->stats();
  gl_out_.allocate(400, 300);
  gl_->draw(req, gl_out_);
  // x: floor(10.3) - 1 = 9 .. ceil(100.2) + 1 = 102; y: 19 .. 82 -> 93 x 63 texels of 4 bytes.
  EXPECT_EQ(gl_->stats().video_bytes_uploaded - before.video_bytes_uploaded, 93u * 63u * 4u);
  EXPECT_EQ(gl_->stats().video_uploads - before.video_uploads, 1u);
  gl_->draw(req, gl_out_);  // same frame, same region (e.g. the other eye): no upload
  EXPECT_EQ(gl_->stats().video_uploads - before.video_uploads, 1u);
  frame_.sequence = ++sequence_;
  req.region = {0.0, 0.0, 480.0, 360.0};
  gl_->draw(req, gl_out_);
  EXPECT_EQ(gl_->stats().video_bytes_uploaded - before.video_bytes_uploaded,
            93u * 63u * 4u + 480u * 360u * 4u);
}

TEST_F(GlCompositorTest, RegionFromMeasureViewIsEnoughForTheWholePicture) {
  // The eye sees only part of the frame; uploading only core's update region must still give the
  // CPU reference's picture (which samples the whole frame).
  CompositeRequest req = base_request();
  req.eye = pinhole(700.0, 400, 300);  // narrow field of view: a small part of the frame
  req.T_world_eye = look_pose(8.0, -4.0, {0.1, 0.0, 0.2});
  hd::core::ViewSetup s;
  s.real = req.real;
  s.T_world_real = req.T_world_real;
  s.virt = req.eye;
  s.T_world_virt = req.T_world_eye;
  s.d_m = req.d_m;
  s.near_m = req.near_m;
  s.workspace.min_m = {-1.5, -1.0, 0.0};
  s.workspace.max_m = {1.5, 0.5, 2.5};
  const hd::core::ViewMeasure m = hd::core::measure_view(s);
  ASSERT_TRUE(m.has_region);
  req.region = m.region;
  frame_.sequence = ++sequence_;
  const auto before = gl_->stats().video_bytes_uploaded;
  draw_both(req, 400, 300);
  const uint64_t uploaded = gl_->stats().video_bytes_uploaded - before;
  EXPECT_LT(uploaded, 480u * 360u * 4u / 2u);  // well under the full frame
  EXPECT_GT(uploaded, 0u);
  EXPECT_GE(psnr_db(cpu_out_, gl_out_), 40.0);
}

TEST_F(GlCompositorTest, PresentBlitsToTheWindowWithoutDisturbingTheNextPicture) {
  CompositeRequest req = base_request();
  draw_both(req, 400, 300);
  gl_->present();
  ImageRgba8 again;
  again.allocate(400, 300);
  gl_->draw(req, again);
  EXPECT_EQ(again.data, gl_out_.data);
  EXPECT_GE(psnr_db(cpu_out_, again), 40.0);
}

TEST_F(GlCompositorTest, MalformedRequestIsRejectedAndCounted) {
  CompositeRequest req = base_request();
  req.viewport = {0, 0, 500, 300};
  gl_out_.allocate(400, 300);
  const auto before = gl_->stats().requests_rejected;
  gl_->draw(req, gl_out_);
  EXPECT_EQ(gl_->stats().requests_rejected, before + 1);
  for (uint8_t b : gl_out_.data) ASSERT_EQ(b, 0);
}

}  // namespace
