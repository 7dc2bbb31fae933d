// The model-depth video view of the CPU reference against independent expectations: a scene of
// photographic quads at several depths rendered exactly from the camera and from the eye (the
// truth), analytic ray casting for what the camera cannot see, and the plane view beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "support/cpu_compositor_scenes.h"
#include "test_paths.h"

namespace {

using namespace hd::render::test;
using hd::core::VideoView;

// A quad facing the cameras at depth z with a crop of a photograph (scenes/textures/) as texture.
TexturedMesh photo_quad(double x0, double y0, double x1, double y1, double z,
                        const std::string& file) {
  TexturedMesh m = facing_quad(x0, y0, x1, y1, z);
  const cv::Mat bgr = cv::imread(std::string(hd::test::source_dir()) + "/scenes/textures/" + file,
                                 cv::IMREAD_COLOR);
  EXPECT_FALSE(bgr.empty()) << file;
  cv::Mat rgba;
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  m.texture.allocate(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y)
    std::memcpy(m.texture.pixel(0, y), rgba.ptr(y), 4 * static_cast<std::size_t>(rgba.cols));
  return m;
}

TexturedMesh uniform_quad(double x0, double y0, double x1, double y1, double z, uint8_t r,
                          uint8_t g, uint8_t b) {
  TexturedMesh m = facing_quad(x0, y0, x1, y1, z);
  for (int y = 0; y < m.texture.height; ++y) {
    for (int x = 0; x < m.texture.width; ++x) {
      uint8_t* p = m.texture.pixel(x, y);
      p[0] = r;
      p[1] = g;
      p[2] = b;
    }
  }
  return m;
}

// The model as the station would hold it: the true geometry with its textures darkened, so a
// pixel filled from the model is told apart from one showing the (true) video.
SyntheticScene darkened(SyntheticScene s) {
  for (TexturedMesh& m : s.meshes)
    for (uint8_t& c : m.texture.data) c = static_cast<uint8_t>(c * 3 / 4);
  ++s.revision;
  return s;
}

// The scene alone (no video, no marking) seen by `eye` at T_world_eye: the exact picture.
ImageRgba8 draw_at(const SyntheticScene& scene, const Pinhole& eye, const Pose& T_world_eye) {
  return draw_model(scene, eye, 0.05, T_world_eye);
}

Frame as_frame(const ImageRgba8& img) {
  Frame f;
  f.allocate_rgba(img.width, img.height);
  for (int y = 0; y < img.height; ++y)
    std::memcpy(f.data.data() + y * f.stride_bytes, img.pixel(0, y), 4 * std::size_t(img.width));
  return f;
}

// PSNR over RGB of the pixels whose video weight is > 0 (all pixels with mask == nullptr).
double psnr_db(const ImageRgba8& a, const ImageRgba8& b, const std::vector<uint8_t>* mask,
               int* pixels = nullptr) {
  double se = 0.0;
  long n = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      if (mask && (*mask)[static_cast<std::size_t>(y) * a.width + x] == 0) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.pixel(x, y)[c]) - double(b.pixel(x, y)[c]);
        se += d * d;
      }
      ++n;
    }
  }
  if (pixels) *pixels = static_cast<int>(n);
  if (n == 0) return 0.0;
  const double mse = se / (3.0 * static_cast<double>(n));
  return mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

struct Drawn {
  ImageRgba8 picture;
  std::vector<uint8_t> weight;  // 0..255 video weight per pixel
};

Drawn draw_view(const SyntheticScene& model, const Frame& frame, const Pinhole& real,
                const Pose& T_wr, const Pinhole& eye, const Pose& T_we, VideoView view, double d_m,
                CpuCompositor* reuse = nullptr) {
  CpuCompositor own;
  CpuCompositor& comp = reuse ? *reuse : own;
  Drawn d;
  d.picture.allocate(eye.width, eye.height);
  comp.record_video_weight(&d.weight);
  CompositeRequest req = video_request(eye, &frame, real);
  req.scene = &model;
  req.T_world_eye = T_we;
  req.T_world_real = T_wr;
  req.d_m = d_m;
  req.video_view = view;
  comp.draw(req, d.picture);
  comp.record_video_weight(nullptr);
  return d;
}

// Back wall at 2.2 m, a board at 1.5 m and a smaller one at 1.0 m, all photographic.
SyntheticScene parallax_scene() {
  SyntheticScene s;
  s.meshes.push_back(photo_quad(-1.2, -0.8, 1.2, 0.8, 2.2, "aloe-wall.png"));
  s.meshes.push_back(photo_quad(-0.45, -0.05, 0.15, 0.35, 1.5, "aloe-cloth-table.png"));
  s.meshes.push_back(photo_quad(0.05, -0.3, 0.3, -0.05, 1.0, "aloe-wall.png"));
  return s;
}

TEST(VideoViews, ModelDepthVideoMatchesTheTruthWithTheHeadOffTheCameraWherePlaneVideoDoesNot) {
  const SyntheticScene truth_scene = parallax_scene();
  const SyntheticScene model = darkened(truth_scene);
  const Pinhole real = pinhole(300.0, 320, 240);
  const Pinhole eye = pinhole(300.0, 320, 240);
  const Pose T_wr = Pose::identity();
  const Pose T_we = look_pose(-4.0, 0.0, {0.25, 0.0, 0.0});
  const Frame frame = as_frame(draw_model(truth_scene, real));  // the camera at the identity
  const ImageRgba8 truth_eye = draw_at(truth_scene, eye, T_we);

  const Drawn depth = draw_view(model, frame, real, T_wr, eye, T_we, VideoView::kModelDepth, 1.5);
  const Drawn plane = draw_view(model, frame, real, T_wr, eye, T_we, VideoView::kPlane, 1.5);
  int depth_px = 0, plane_px = 0;
  const double depth_db = psnr_db(depth.picture, truth_eye, &depth.weight, &depth_px);
  const double plane_db = psnr_db(plane.picture, truth_eye, &plane.weight, &plane_px);
  std::printf(
      "    video pixels: model-depth %d, plane %d; PSNR model-depth %.2f dB, plane %.2f dB\n",
      depth_px, plane_px, depth_db, plane_db);
  // Most of the eye sees what the camera saw (the rest is outside its frustum or behind a board).
  EXPECT_GT(depth_px, eye.width * eye.height * 6 / 10);
  EXPECT_GE(depth_db, 30.0);
  EXPECT_LE(plane_db, depth_db - 8.0);
}

TEST(VideoViews, AtTheCameraPoseModelDepthAndPlaneGiveTheSamePicture) {
  const SyntheticScene truth_scene = parallax_scene();
  const SyntheticScene model = darkened(truth_scene);
  const Pinhole cam = pinhole(300.0, 320, 240);
  const Pose T = look_pose(3.0, -2.0, {0.05, -0.02, 0.1});
  const ImageRgba8 seen = draw_at(truth_scene, cam, T);
  const Frame frame = as_frame(seen);
  const Drawn depth = draw_view(model, frame, cam, T, cam, T, VideoView::kModelDepth, 1.5);
  const Drawn plane = draw_view(model, frame, cam, T, cam, T, VideoView::kPlane, 1.5);
  const Drawn fitted = draw_view(model, frame, cam, T, cam, T, VideoView::kFittedPlane, 2.2);
  int n = 0;
  for (uint8_t w : depth.weight) n += w == 255;
  EXPECT_EQ(n, cam.width * cam.height);  // the camera sees everything it sees
  EXPECT_GE(psnr_db(depth.picture, plane.picture, nullptr), 40.0);
  EXPECT_GE(psnr_db(fitted.picture, plane.picture, nullptr), 40.0);
  EXPECT_GE(psnr_db(depth.picture, seen, nullptr), 40.0);
}

// Wall at 2 m, a grey board at 1 m in front of the camera; the eye 0.25 m to the right sees part
// of the wall the board hides from the camera.
TEST(VideoViews, ADisoccludedRegionIsFilledFromTheModelNotSmearedFromTheVideo) {
  SyntheticScene truth_scene;
  truth_scene.meshes.push_back(photo_quad(-1.2, -0.8, 1.2, 0.8, 2.0, "aloe-wall.png"));
  truth_scene.meshes.push_back(uniform_quad(-0.1, -0.1, 0.1, 0.1, 1.0, 90, 200, 90));
  const SyntheticScene model = darkened(truth_scene);
  const Pinhole cam = pinhole(300.0, 320, 240);
  const Pose T_wr = Pose::identity();
  const Pose T_we = look_pose(0.0, 0.0, {0.25, 0.0, 0.0});
  const Frame frame = as_frame(draw_model(truth_scene, cam));
  const ImageRgba8 model_view = draw_at(model, cam, T_we);
  // Ray casting: the eye pixel (x, y) sees the wall at a point the board hides from the camera.
  auto hidden_wall = [&](double x, double y) {
    const Eigen::Vector3d dir((x + 0.5 - cam.cx) / cam.fx, (y + 0.5 - cam.cy) / cam.fy, 1.0);
    const Eigen::Vector3d o = T_we.t;
    const Eigen::Vector3d on_board = o + dir * (1.0 - o.z());
    if (std::abs(on_board.x()) < 0.1 && std::abs(on_board.y()) < 0.1) return false;  // board
    const Eigen::Vector3d X = o + dir * (2.0 - o.z());
    const Eigen::Vector3d through = X / X.z();  // where the camera's ray to X crosses z = 1
    return std::abs(through.x()) < 0.1 && std::abs(through.y()) < 0.1;
  };
  const Drawn depth = draw_view(model, frame, cam, T_wr, cam, T_we, VideoView::kModelDepth, 2.0);
  const Drawn plane = draw_view(model, frame, cam, T_wr, cam, T_we, VideoView::kPlane, 2.0);
  int hidden = 0, depth_video = 0, depth_not_model = 0, plane_video = 0;
  for (int y = 2; y < cam.height - 2; ++y) {
    for (int x = 2; x < cam.width - 2; ++x) {
      // Two pixels away from the region's edges: the rasterisers' edge rules do not matter.
      bool inside = true;
      for (int dy = -2; dy <= 2 && inside; dy += 2)
        for (int dx = -2; dx <= 2 && inside; dx += 2) inside = hidden_wall(x + dx, y + dy);
      if (!inside) continue;
      ++hidden;
      const std::size_t i = static_cast<std::size_t>(y) * cam.width + x;
      depth_video += depth.weight[i] > 0;
      depth_not_model += std::memcmp(depth.picture.pixel(x, y), model_view.pixel(x, y), 3) != 0;
      plane_video += plane.weight[i] > 0;
    }
  }
  std::printf("    hidden wall pixels %d: model-depth shows video on %d, plane on %d\n", hidden,
              depth_video, plane_video);
  EXPECT_GT(hidden, 1000);
  EXPECT_EQ(depth_video, 0);
  EXPECT_EQ(depth_not_model, 0);
  EXPECT_EQ(plane_video, hidden);  // the plane smears the board's video over them
}

TEST(VideoViews, TheCameraDepthMapIsDrawnOncePerModelAndCameraNotPerFrame) {
  SyntheticScene model = parallax_scene();
  const Pinhole cam = pinhole(300.0, 320, 240);
  const Frame frame = uniform_frame(320, 240, 10, 20, 30);
  CpuCompositor comp;
  const Pose T_we = look_pose(-4.0, 0.0, {0.25, 0.0, 0.0});
  for (int i = 0; i < 3; ++i)
    draw_view(model, frame, cam, Pose::identity(), cam, T_we, VideoView::kModelDepth, 1.5, &comp);
  EXPECT_EQ(comp.stats().camera_depth_renders, 1u);
  ++model.revision;  // a model update
  draw_view(model, frame, cam, Pose::identity(), cam, T_we, VideoView::kModelDepth, 1.5, &comp);
  EXPECT_EQ(comp.stats().camera_depth_renders, 2u);
  draw_view(model, frame, cam, look_pose(1.0, 0.0, {0.0, 0.0, 0.0}), cam, T_we,
            VideoView::kModelDepth, 1.5, &comp);  // the camera moved
  EXPECT_EQ(comp.stats().camera_depth_renders, 3u);
  draw_view(model, frame, cam, Pose::identity(), cam, T_we, VideoView::kPlane, 1.5, &comp);
  EXPECT_EQ(comp.stats().camera_depth_renders, 3u);  // the plane view needs none
}

}  // namespace
