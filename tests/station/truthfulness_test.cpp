// Is the video view truthful? A scene of one plane of Gaussian dots at depth D in front of a real
// camera. The camera's frame is the CPU compositor's exact render of that plane from the camera;
// the station shows that frame as video only (w_video = 1, no marks) projected on z_c = d. The
// composited picture is compared with the exact render of the plane from the eye, dot by dot,
// with dot centres found by an intensity-weighted centroid (independent of core's geometry):
//   D = d : the video is exact at any eye pose (core's E = 0; measured shift < 0.1 px);
//   D != d: each dot's measured shift equals core's E at the dot's centre within 0.1 px (the issue
//           asks for 1 px), and the largest shift matches core's m (= E_max, coverage being 1)
//           over the visible part within 0.1 px.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "core/reprojection_error.h"
#include "core/view_measure.h"
#include "render/compositor/cpu_compositor.h"

namespace {

using hd::core::Pinhole;
using hd::core::Pose;
using hd::render::CompositeRequest;
using hd::render::CpuCompositor;
using hd::render::ImageRgba8;
using hd::render::SyntheticScene;
using hd::render::TexturedMesh;

// The plane: 1.2 m x 0.9 m, 1 mm texels, a 7 x 5 grid of dots 0.13 m apart, Gaussian sigma 1 cm.
constexpr double kPlaneW_m = 1.2, kPlaneH_m = 0.9;
constexpr int kTexW = 1200, kTexH = 900;
constexpr int kCols = 7, kRows = 5;
constexpr double kSpacing_m = 0.13, kSigma_m = 0.01;
constexpr int kWindowRadius_px = 24;  // >= 3.7 sigma at the nearest eye, < half the dot spacing

// The real camera: axis-aligned (so the dot rectangle is a flat workspace box), off the origin.
const Pinhole kReal = Pinhole::centred(400.0, 640, 480);
const Pose kTWorldReal{Eigen::Matrix3d::Identity(), {0.02, -0.05, 0.1}};
const Pinhole kEye = Pinhole::centred(450.0, 480, 360);

Eigen::Matrix3d rot(double angle_rad, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
}

// Dot centres in the real camera's frame, on z_c = D.
std::vector<Eigen::Vector3d> dots_camera(double D_m) {
  std::vector<Eigen::Vector3d> out;
  for (int r = 0; r < kRows; ++r)
    for (int c = 0; c < kCols; ++c)
      out.emplace_back((c - (kCols - 1) / 2.0) * kSpacing_m, (r - (kRows - 1) / 2.0) * kSpacing_m,
                       D_m);
  return out;
}

// The plane z_c = D as a textured quad; texel (i, j) has its centre at plane point
// (-W/2 + (i+0.5) W/w, -H/2 + (j+0.5) H/h) (TexturedMesh's texel convention).
SyntheticScene plane_scene(double D_m) {
  TexturedMesh m;
  const double hx = kPlaneW_m / 2, hy = kPlaneH_m / 2;
  const Eigen::Vector3d corners[4] = {
      {-hx, -hy, D_m}, {hx, -hy, D_m}, {hx, hy, D_m}, {-hx, hy, D_m}};
  const Eigen::Vector2f uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int i = 0; i < 4; ++i) {
    m.positions_m.push_back(kTWorldReal.to_world(corners[i]).cast<float>());
    m.uvs.push_back(uvs[i]);
  }
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(kTexW, kTexH);
  const auto dots = dots_camera(D_m);
  for (int j = 0; j < kTexH; ++j) {
    for (int i = 0; i < kTexW; ++i) {
      const double x = -hx + (i + 0.5) * kPlaneW_m / kTexW;
      const double y = -hy + (j + 0.5) * kPlaneH_m / kTexH;
      double v = 0.0;
      for (const auto& d : dots) {
        const double r2 = (x - d.x()) * (x - d.x()) + (y - d.y()) * (y - d.y());
        if (r2 < 16 * kSigma_m * kSigma_m) v += std::exp(-r2 / (2 * kSigma_m * kSigma_m));
      }
      uint8_t* p = m.texture.pixel(i, j);
      p[0] = p[1] = p[2] = static_cast<uint8_t>(std::lround(255.0 * std::min(v, 1.0)));
      p[3] = 255;
    }
  }
  SyntheticScene s;
  s.meshes.push_back(std::move(m));
  s.background_rgb = {0, 0, 0};
  return s;
}

CompositeRequest base_request(const Pinhole& eye, const Pose& T_world_eye) {
  CompositeRequest r;
  r.eye = eye;
  r.T_world_eye = T_world_eye;
  r.near_m = 0.05;
  r.far_m = 10.0;
  r.viewport = {0, 0, eye.width, eye.height};
  r.marking.style = hd::core::MarkingStyle::kNone;
  return r;
}

// The exact picture of `scene` from a camera (synthetic only).
ImageRgba8 render_exact(CpuCompositor& c, const SyntheticScene& scene, const Pinhole& cam,
                        const Pose& T_world_cam) {
  CompositeRequest r = base_request(cam, T_world_cam);
  r.scene = &scene;
  ImageRgba8 out;
  out.allocate(cam.width, cam.height);
  c.draw(r, out);
  return out;
}

hd::core::ViewSetup setup_for(const Pose& T_world_eye, double d_m, double D_m) {
  hd::core::ViewSetup s;
  s.real = kReal;
  s.T_world_real = kTWorldReal;
  s.virt = kEye;
  s.T_world_virt = T_world_eye;
  s.d_m = d_m;
  s.near_m = 0.05;
  // W: the dot rectangle itself (a flat box, the plane being normal to world z).
  const auto dots = dots_camera(D_m);
  s.workspace.min_m = kTWorldReal.to_world(dots.front());
  s.workspace.max_m = kTWorldReal.to_world(dots.back());
  return s;
}

// The station's picture: the frame as video only, projected on z_c = d, nothing synthetic.
ImageRgba8 render_video(CpuCompositor& c, const hd::drivers::Frame& frame, const Pose& T_world_eye,
                        double d_m, const hd::core::ViewMeasure& vm) {
  static const SyntheticScene kEmpty = [] {
    SyntheticScene s;
    s.background_rgb = {0, 0, 0};
    return s;
  }();
  CompositeRequest r = base_request(kEye, T_world_eye);
  r.scene = &kEmpty;
  r.video = &frame;
  r.real = kReal;
  r.T_world_real = kTWorldReal;
  r.d_m = d_m;
  r.region = vm.region;
  r.has_region = vm.has_region;
  r.transition = {hd::core::Variant::kVideo, 1.0, 0.0};
  r.mode = hd::core::TransitionMode::kAbrupt;
  ImageRgba8 out;
  out.allocate(kEye.width, kEye.height);
  c.draw(r, out);
  return out;
}

// Intensity-weighted centroid (R+G+B) in a square window, re-centred on the result until it
// settles; nullopt if the window leaves the image or holds no light. Pixel (x, y) sits at
// (x + 0.5, y + 0.5) in continuous image coordinates.
std::optional<Eigen::Vector2d> centroid(const ImageRgba8& img, Eigen::Vector2d seed) {
  for (int iter = 0; iter < 20; ++iter) {
    const int x0 = static_cast<int>(std::floor(seed.x())) - kWindowRadius_px;
    const int y0 = static_cast<int>(std::floor(seed.y())) - kWindowRadius_px;
    const int n = 2 * kWindowRadius_px + 1;
    if (x0 < 0 || y0 < 0 || x0 + n > img.width || y0 + n > img.height) return std::nullopt;
    double sw = 0, sx = 0, sy = 0;
    for (int y = y0; y < y0 + n; ++y) {
      for (int x = x0; x < x0 + n; ++x) {
        const uint8_t* p = img.pixel(x, y);
        const double w = p[0] + p[1] + p[2];
        sw += w;
        sx += w * (x + 0.5);
        sy += w * (y + 0.5);
      }
    }
    if (sw < 255.0) return std::nullopt;
    const Eigen::Vector2d c(sx / sw, sy / sw);
    const bool settled = (c - seed).norm() < 1e-4;
    seed = c;
    if (settled) break;
  }
  return seed;
}

hd::drivers::Frame frame_from(const ImageRgba8& img) {
  hd::drivers::Frame f;
  f.allocate_rgba(img.width, img.height);
  for (int y = 0; y < img.height; ++y)
    std::copy(img.row(y), img.row(y) + 4 * img.width, f.data.data() + y * f.stride_bytes);
  return f;
}

// An eye placed at `offset` from the real camera, turned by yaw (about y) and pitch (about x).
Pose eye_pose(const Eigen::Vector3d& offset_m, double yaw_rad, double pitch_rad) {
  return {rot(yaw_rad, Eigen::Vector3d::UnitY()) * rot(pitch_rad, Eigen::Vector3d::UnitX()),
          kTWorldReal.t + offset_m};
}

struct DotResult {
  Eigen::Vector3d X_world;
  Eigen::Vector2d exact_px, video_px;
};

// Renders both pictures for one eye pose and measures every dot seen in both.
std::vector<DotResult> measure_dots(CpuCompositor& c, const SyntheticScene& scene,
                                    const hd::drivers::Frame& frame, const Pose& T_world_eye,
                                    double d_m, double D_m, hd::core::ViewMeasure* vm_out) {
  const hd::core::ViewMeasure vm = hd::core::measure_view(setup_for(T_world_eye, d_m, D_m));
  if (vm_out) *vm_out = vm;
  const ImageRgba8 exact = render_exact(c, scene, kEye, T_world_eye);
  const ImageRgba8 video = render_video(c, frame, T_world_eye, d_m, vm);
  std::vector<DotResult> out;
  for (const auto& Xc : dots_camera(D_m)) {
    const Eigen::Vector3d X = kTWorldReal.to_world(Xc);
    // Seeds from the test's own ray geometry: X, and X'' = (d / D) X_c on the real camera's ray.
    const Eigen::Vector3d Xe = T_world_eye.to_camera(X);
    const Eigen::Vector3d Xe2 = T_world_eye.to_camera(kTWorldReal.to_world(Xc * (d_m / D_m)));
    if (Xe.z() < 0.1 || Xe2.z() < 0.1) continue;
    const auto ce = centroid(exact, kEye.project(Xe));
    const auto cv = centroid(video, kEye.project(Xe2));
    if (ce && cv) out.push_back({X, *ce, *cv});
  }
  return out;
}

class Truthfulness : public ::testing::Test {
 protected:
  static constexpr double kD_m = 1.0;  // the plane's true depth D
  void SetUp() override {
    scene_ = plane_scene(kD_m);
    frame_ = frame_from(render_exact(compositor_, scene_, kReal, kTWorldReal));
  }
  CpuCompositor compositor_{1};
  SyntheticScene scene_;
  hd::drivers::Frame frame_;
};

TEST_F(Truthfulness, PlaneAtDIsShownExactlyFromAnyEyePose) {
  // Eye poses spread over the workspace: 0.5 m across, 0.4 m in depth, turned up to ~6 deg.
  std::vector<Pose> poses;
  for (double tx : {-0.25, 0.0, 0.25})
    for (double ty : {-0.15, 0.15})
      for (double tz : {-0.1, 0.3})
        poses.push_back(eye_pose({tx, ty, tz}, -0.4 * tx - 0.05 * ty, 0.5 * ty + 0.02 * tx));
  double worst_px = 0.0;
  std::size_t measured = 0;
  for (const Pose& P : poses) {
    const hd::core::ViewSetup s = setup_for(P, kD_m, kD_m);
    const auto dots = measure_dots(compositor_, scene_, frame_, P, kD_m, kD_m, nullptr);
    EXPECT_GE(dots.size(), 12u) << "most dots must be seen from pose at " << P.t.transpose();
    for (const auto& d : dots) {
      const auto E = hd::core::reprojection_error(s, d.X_world);
      ASSERT_TRUE(E.has_value());
      EXPECT_LT(*E, 1e-9) << "core: a point on the plane z_c = d has E = 0";
      const double shift = (d.video_px - d.exact_px).norm();
      worst_px = std::max(worst_px, shift);
      EXPECT_LT(shift, 0.1) << "dot at " << d.X_world.transpose() << " eye at " << P.t.transpose();
    }
    measured += dots.size();
  }
  EXPECT_GE(measured, 250u);
  std::printf("D = d: %zu dots over %zu eye poses, largest measured shift %.4f px\n", measured,
              poses.size(), worst_px);
  RecordProperty("largest_shift_px_milli", static_cast<int>(std::lround(worst_px * 1000)));
}

TEST_F(Truthfulness, PlaneOffDShiftsEachDotByCoreE) {
  // Eyes near the camera (coverage 1, every dot seen), video projected too near or too far.
  std::vector<Pose> poses;
  for (double tx : {-0.08, 0.08})
    for (double ty : {-0.05, 0.06}) poses.push_back(eye_pose({tx, ty, -0.05}, -0.4 * tx, 0.4 * ty));
  poses.push_back(eye_pose({0.0, 0.0, 0.03}, 0.02, -0.03));
  // The issue asks for 1 px; the measurement agrees to ~0.03 px, so a tenth of a pixel is asserted.
  constexpr double kAgree_px = 0.1;
  double worst_dot_err = 0.0, worst_max_err = 0.0, largest_E = 0.0;
  for (double d_m : {0.7, 1.5}) {
    for (const Pose& P : poses) {
      const hd::core::ViewSetup s = setup_for(P, d_m, kD_m);
      hd::core::ViewMeasure vm{};
      const auto dots = measure_dots(compositor_, scene_, frame_, P, d_m, kD_m, &vm);
      ASSERT_EQ(dots.size(), static_cast<std::size_t>(kCols * kRows))
          << "every dot must be seen, d = " << d_m << " eye at " << P.t.transpose();
      double max_shift = 0.0;
      for (const auto& d : dots) {
        const auto E = hd::core::reprojection_error(s, d.X_world);
        ASSERT_TRUE(E.has_value());
        const double shift = (d.video_px - d.exact_px).norm();
        EXPECT_NEAR(shift, *E, kAgree_px) << "dot at " << d.X_world.transpose() << ", d = " << d_m;
        worst_dot_err = std::max(worst_dot_err, std::abs(shift - *E));
        max_shift = std::max(max_shift, shift);
        largest_E = std::max(largest_E, *E);
      }
      EXPECT_GT(max_shift, 2.0) << "the shift must be large enough to mean something";
      // W is the dot rectangle (all of it in view), the video covers the whole eye picture, so
      // m = E_max / 1 is core's largest error over what is seen.
      EXPECT_NEAR(vm.coverage, 1.0, 1e-9);
      EXPECT_NEAR(max_shift, vm.m, kAgree_px) << "d = " << d_m << " eye at " << P.t.transpose();
      worst_max_err = std::max(worst_max_err, std::abs(max_shift - vm.m));
    }
  }
  EXPECT_GT(largest_E, 15.0);
  std::printf(
      "D != d: largest |shift - E| per dot %.4f px, largest |max shift - m| %.4f px, largest E "
      "%.2f px\n",
      worst_dot_err, worst_max_err, largest_E);
}

TEST_F(Truthfulness, CentroidFindsAKnownSubPixelShift) {
  // The measuring method on its own: the exact render of the plane moved by a known amount along
  // the camera x axis shifts every dot by f * dx / z in the image (a pure translation parallel to
  // the plane is a pure image shift), which the centroid must recover.
  const Pose P0 = eye_pose({0.0, 0.0, 0.0}, 0.0, 0.0);
  const double dx_m = 0.0003;  // 0.135 px at f = 450, z = 1.0 m
  Pose P1 = P0;
  P1.t.x() -= dx_m;  // eye moves left, the picture moves right
  const ImageRgba8 a = render_exact(compositor_, scene_, kEye, P0);
  const ImageRgba8 b = render_exact(compositor_, scene_, kEye, P1);
  double worst = 0.0;
  for (const auto& Xc : dots_camera(kD_m)) {
    const Eigen::Vector3d Xe = P0.to_camera(kTWorldReal.to_world(Xc));
    const auto ca = centroid(a, kEye.project(Xe));
    const auto cb = centroid(b, kEye.project(Xe));
    ASSERT_TRUE(ca && cb);
    const double expect_px = kEye.fx * dx_m / Xe.z();
    worst = std::max(worst, std::abs((*cb - *ca).x() - expect_px));
    EXPECT_NEAR((*cb - *ca).y(), 0.0, 0.02);
  }
  EXPECT_LT(worst, 0.02);
  std::printf("centroid: known 0.135 px shift recovered within %.4f px\n", worst);
}

}  // namespace
