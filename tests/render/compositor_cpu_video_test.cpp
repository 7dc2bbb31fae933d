// The CPU reference compositor's video against independent expectations: identical cameras
// reproduce the frame, the warp follows an analytic ray/plane mapping, and the per-pixel and
// global blend weights are the paper's, written out here.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "support/cpu_compositor_scenes.h"

namespace {

using namespace hd::render::test;

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

}  // namespace

namespace {

// What `hybrid-station score` keeps of a draw: the model view is the model drawn alone, and the
// positions are where the analytic ray/plane mapping meets the frame (NaN where it misses).
TEST(CpuCompositor, TheRecordsKeepTheModelViewAndWhereTheVideoWasSampled) {
  const Pinhole eye = pinhole(300.0, 160, 120);
  const Pinhole real = pinhole(500.0, 160, 120);  // narrower: the video covers the middle
  const Frame frame = coded_frame(160, 120);
  SyntheticScene scene;
  scene.background_rgb = {1, 2, 3};
  scene.meshes.push_back(facing_quad(-0.6, -0.4, 0.5, 0.45, 2.5));
  for (int threads : {1, 2}) {
    CpuCompositor comp(threads);
    ImageRgba8 out, model;
    std::vector<float> positions;
    comp.record_model_only(&model);
    comp.record_video_positions(&positions);
    out.allocate(160, 120);
    CompositeRequest req = video_request(eye, &frame, real);
    req.scene = &scene;
    comp.draw(req, out);
    EXPECT_EQ(model.data, draw_model(scene, eye).data) << "threads " << threads;
    ASSERT_EQ(positions.size(), 2u * 160 * 120);
    int inside = 0, outside = 0, wrong = 0;
    for (int y = 0; y < 120; ++y)
      for (int x = 0; x < 160; ++x) {
        double u = 0, v = 0;
        analytic_real_pixel(eye, Pose::identity(), real, Pose::identity(), 2.0, x, y, &u, &v);
        const float pu = positions[2 * (y * 160 + x)], pv = positions[2 * (y * 160 + x) + 1];
        if (u < 0.01 || v < 0.01 || u > 159.99 || v > 119.99) {  // clear of the frame's edge
          if (u < -0.01 || v < -0.01 || u > 160.01 || v > 120.01) {
            ++outside;
            wrong += std::isnan(pu) && std::isnan(pv) ? 0 : 1;
          }
          continue;
        }
        ++inside;
        wrong += std::abs(pu - u) < 1e-3 && std::abs(pv - v) < 1e-3 ? 0 : 1;
      }
    EXPECT_GT(inside, 5000);
    EXPECT_GT(outside, 5000);
    EXPECT_EQ(wrong, 0) << "threads " << threads;
  }
}

}  // namespace
