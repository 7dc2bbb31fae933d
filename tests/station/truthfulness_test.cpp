// Is the video view truthful? A scene of one plane of Gaussian dots at depth D in front of a real
// camera. The camera's frame is the plane drawn analytically (a ray per pixel centre, the dot
// function evaluated where it meets the plane); the station shows that frame as video only
// (w_video = 1, no marks) projected on z_c = d through the CPU compositor under test. Nothing the
// picture is compared with comes from the compositor (before, the truth and the frame were the
// compositor's own renders, so a fault shared by its paths could pass):
//   - the truth: the same analytic drawing of the plane from the eye;
//   - the warp's reference: OpenCV's cv::warpPerspective of the frame with the plane homography
//     the test derives itself.
// Dots are located by an intensity-weighted centroid (independent of core's geometry):
//   D = d : the video shows every dot where the truth has it, at any eye pose (core's E = 0);
//   D != d: each dot's measured shift from the truth equals core's E at the dot's centre (the
//           issue asks for 1 px), and the largest shift matches core's m (= E_max, coverage
//           being 1) over the visible part;
//   any d : the compositor's picture matches cv::warpPerspective's, dot for dot.
// Measured (the computation is deterministic; each test records its largest residual as a
// property, --gtest_output=xml): video against the truth within 0.026 px, video against OpenCV
// within 0.022 px, OpenCV against the truth within 0.021 px; asserted 0.05 and 0.04 px. Checked by
// breaking the warp (render/compositor/ video_warp.cpp, cpu_compositor.cpp): the eye's c_x moved
// 0.1 px (worst dot 0.13 px off), the frame's c_x moved 0.1 px (0.17 px), d off by 1 % (2.7 px),
// the texel sampling moved 1/8 px (0.31 px) each fail both compositor tests.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
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

// The plane: 1.2 m x 0.9 m, a 7 x 5 grid of dots 0.13 m apart, Gaussian sigma 1 cm (cut off at
// 4 sigma, so at most one dot lights any point: the spacing is over 8 sigma).
constexpr double kPlaneW_m = 1.2, kPlaneH_m = 0.9;
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

// The plane's brightness (0..1) at (x, y) of its own frame (the real camera's x, y on z_c = D);
// nullopt off the plane.
std::optional<double> plane_value(double x, double y) {
  if (std::abs(x) > kPlaneW_m / 2 || std::abs(y) > kPlaneH_m / 2) return std::nullopt;
  const double c = std::clamp(std::round(x / kSpacing_m + (kCols - 1) / 2.0), 0.0, kCols - 1.0);
  const double r = std::clamp(std::round(y / kSpacing_m + (kRows - 1) / 2.0), 0.0, kRows - 1.0);
  const double dx = x - (c - (kCols - 1) / 2.0) * kSpacing_m;
  const double dy = y - (r - (kRows - 1) / 2.0) * kSpacing_m;
  const double r2 = dx * dx + dy * dy;
  return r2 < 16 * kSigma_m * kSigma_m ? std::exp(-r2 / (2 * kSigma_m * kSigma_m)) : 0.0;
}

// The plane z_c = D drawn by a camera (intrinsics `cam`, pose `T_world_cam`) without the
// compositor: each pixel centre (x + 0.5, y + 0.5) casts its ray (the pinhole written out here,
// not core's), and the pixel is the plane's value where the ray meets it, rounded to 8 bits
// (black off the plane). Writes `width` x `height` RGBA rows `stride` bytes apart.
void draw_plane(const Pinhole& cam, const Pose& T_world_cam, double D_m, uint8_t* data,
                int stride) {
  // The ray in the real camera's frame: origin o, direction R_rc * (pixel ray).
  const Eigen::Matrix3d R_rc = kTWorldReal.R.transpose() * T_world_cam.R;
  const Eigen::Vector3d o = kTWorldReal.R.transpose() * (T_world_cam.t - kTWorldReal.t);
  for (int y = 0; y < cam.height; ++y) {
    uint8_t* row = data + static_cast<std::ptrdiff_t>(y) * stride;
    for (int x = 0; x < cam.width; ++x) {
      const Eigen::Vector3d ray((x + 0.5 - cam.cx) / cam.fx, (y + 0.5 - cam.cy) / cam.fy, 1.0);
      const Eigen::Vector3d dir = R_rc * ray;
      double v = 0.0;
      if (dir.z() > 1e-9) {
        const double s = (D_m - o.z()) / dir.z();
        if (s > 0) v = plane_value(o.x() + s * dir.x(), o.y() + s * dir.y()).value_or(0.0);
      }
      uint8_t* p = row + 4 * x;
      p[0] = p[1] = p[2] = static_cast<uint8_t>(std::lround(255.0 * v));
      p[3] = 255;
    }
  }
}

ImageRgba8 truth_picture(const Pose& T_world_eye, double D_m) {
  ImageRgba8 out;
  out.allocate(kEye.width, kEye.height);
  draw_plane(kEye, T_world_eye, D_m, out.data.data(), out.stride_bytes);
  return out;
}

hd::drivers::Frame camera_frame(double D_m) {
  hd::drivers::Frame f;
  f.allocate_rgba(kReal.width, kReal.height);
  draw_plane(kReal, kTWorldReal, D_m, f.data.data(), f.stride_bytes);
  return f;
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

// The station's picture (the code under test): the frame as video only, projected on z_c = d,
// nothing synthetic.
ImageRgba8 station_picture(CpuCompositor& c, const hd::drivers::Frame& frame,
                           const Pose& T_world_eye, double d_m, const hd::core::ViewMeasure& vm) {
  static const SyntheticScene kEmpty = [] {
    SyntheticScene s;
    s.background_rgb = {0, 0, 0};
    return s;
  }();
  CompositeRequest r;
  r.eye = kEye;
  r.T_world_eye = T_world_eye;
  r.near_m = 0.05;
  r.far_m = 10.0;
  r.viewport = {0, 0, kEye.width, kEye.height};
  r.marking.style = hd::core::MarkingStyle::kNone;
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
  EXPECT_EQ(c.stats().requests_rejected, 0u);
  return out;
}

// The homography the video warp must apply, derived here: eye pixel (OpenCV's convention, centre
// at integers) -> frame pixel. An eye ray r (eye frame) meets z_c = d at X_c = lambda R_ce r + t_ce
// with lambda = (d - t_ce.z) / (R_ce r).z, so X_c is proportional to
// ((d - t_ce.z) I + t_ce e_z^T) R_ce r.
cv::Matx33d plane_homography_cv(const Pose& T_world_eye, double d_m) {
  const Eigen::Matrix3d R_ce = kTWorldReal.R.transpose() * T_world_eye.R;
  const Eigen::Vector3d t_ce = kTWorldReal.R.transpose() * (T_world_eye.t - kTWorldReal.t);
  const Eigen::Matrix3d M = ((d_m - t_ce.z()) * Eigen::Matrix3d::Identity() +
                             t_ce * Eigen::Vector3d::UnitZ().transpose()) *
                            R_ce;
  auto K = [](const Pinhole& p) {
    Eigen::Matrix3d k;
    k << p.fx, 0, p.cx, 0, p.fy, p.cy, 0, 0, 1;
    return k;
  };
  Eigen::Matrix3d half;  // continuous (centre at +0.5) = half * OpenCV pixel
  half << 1, 0, 0.5, 0, 1, 0.5, 0, 0, 1;
  const Eigen::Matrix3d H = half.inverse() * K(kReal) * M * K(kEye).inverse() * half;
  cv::Matx33d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = H(i, j);
  return out;
}

// OpenCV's picture of the frame on z_c = d (bilinear, black outside the frame).
ImageRgba8 opencv_picture(const hd::drivers::Frame& frame, const Pose& T_world_eye, double d_m) {
  const cv::Mat src(frame.height, frame.width, CV_8UC4, const_cast<uint8_t*>(frame.data.data()),
                    static_cast<std::size_t>(frame.stride_bytes));
  ImageRgba8 out;
  out.allocate(kEye.width, kEye.height);
  cv::Mat dst(out.height, out.width, CV_8UC4, out.data.data(),
              static_cast<std::size_t>(out.stride_bytes));
  cv::warpPerspective(src, dst, plane_homography_cv(T_world_eye, d_m), dst.size(),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT,
                      cv::Scalar(0, 0, 0, 255));
  return out;
}

// A picture's pixels, whoever owns them.
struct View {
  const uint8_t* data;
  int width, height, stride;
  View(const ImageRgba8& i)
      : data(i.data.data()), width(i.width), height(i.height), stride(i.stride_bytes) {}
  View(const hd::drivers::Frame& f)
      : data(f.data.data()), width(f.width), height(f.height), stride(f.stride_bytes) {}
};

// Intensity-weighted centroid (R+G+B) in a square window, re-centred on the result until it
// settles; nullopt if the window leaves the image or holds no light. Pixel (x, y) sits at
// (x + 0.5, y + 0.5) in continuous image coordinates.
std::optional<Eigen::Vector2d> centroid(View img, Eigen::Vector2d seed) {
  for (int iter = 0; iter < 20; ++iter) {
    const int x0 = static_cast<int>(std::floor(seed.x())) - kWindowRadius_px;
    const int y0 = static_cast<int>(std::floor(seed.y())) - kWindowRadius_px;
    const int n = 2 * kWindowRadius_px + 1;
    if (x0 < 0 || y0 < 0 || x0 + n > img.width || y0 + n > img.height) return std::nullopt;
    double sw = 0, sx = 0, sy = 0;
    for (int y = y0; y < y0 + n; ++y) {
      for (int x = x0; x < x0 + n; ++x) {
        const uint8_t* p = img.data + static_cast<std::ptrdiff_t>(y) * img.stride + 4 * x;
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

// An eye placed at `offset` from the real camera, turned by yaw (about y) and pitch (about x).
Pose eye_pose(const Eigen::Vector3d& offset_m, double yaw_rad, double pitch_rad) {
  return {rot(yaw_rad, Eigen::Vector3d::UnitY()) * rot(pitch_rad, Eigen::Vector3d::UnitX()),
          kTWorldReal.t + offset_m};
}

struct DotResult {
  Eigen::Vector3d X_world;
  Eigen::Vector2d truth_px, video_px, opencv_px;
};

// Draws the three pictures for one eye pose and measures every dot seen in all of them.
std::vector<DotResult> measure_dots(CpuCompositor& c, const hd::drivers::Frame& frame,
                                    const Pose& T_world_eye, double d_m, double D_m,
                                    hd::core::ViewMeasure* vm_out) {
  const hd::core::ViewMeasure vm = hd::core::measure_view(setup_for(T_world_eye, d_m, D_m));
  if (vm_out) *vm_out = vm;
  const ImageRgba8 truth = truth_picture(T_world_eye, D_m);
  const ImageRgba8 video = station_picture(c, frame, T_world_eye, d_m, vm);
  const ImageRgba8 opencv = opencv_picture(frame, T_world_eye, d_m);
  std::vector<DotResult> out;
  for (const auto& Xc : dots_camera(D_m)) {
    const Eigen::Vector3d X = kTWorldReal.to_world(Xc);
    // Seeds from the test's own ray geometry: X, and X'' = (d / D) X_c on the real camera's ray.
    const Eigen::Vector3d Xe = T_world_eye.to_camera(X);
    const Eigen::Vector3d Xe2 = T_world_eye.to_camera(kTWorldReal.to_world(Xc * (d_m / D_m)));
    if (Xe.z() < 0.1 || Xe2.z() < 0.1) continue;
    const auto ct = centroid(truth, kEye.project(Xe));
    const auto cv = centroid(video, kEye.project(Xe2));
    const auto co = centroid(opencv, kEye.project(Xe2));
    if (ct && cv && co) out.push_back({X, *ct, *cv, *co});
  }
  return out;
}

// The bounds (see the top of the file for what was measured and how they were checked).
constexpr double kTruth_px = 0.05;
constexpr double kOpenCv_px = 0.04;

// The largest of a residual, recorded as a test property (--gtest_output=xml shows it), so the
// figures docs/tracking.md quotes come from the asserted values themselves.
struct Largest {
  const char* name;
  double value = 0.0;
  void add(double x) { value = std::max(value, x); }
  ~Largest() {
    char text[32];
    std::snprintf(text, sizeof text, "%.4f", value);
    ::testing::Test::RecordProperty(name, text);
  }
};

class Truthfulness : public ::testing::Test {
 protected:
  static constexpr double kD_m = 1.0;  // the plane's true depth D
  CpuCompositor compositor_{1};
  hd::drivers::Frame frame_ = camera_frame(kD_m);
};

TEST_F(Truthfulness, PlaneAtDIsShownExactlyFromAnyEyePose) {
  // Eye poses spread over the workspace: 0.5 m across, 0.4 m in depth, turned up to ~6 deg.
  std::vector<Pose> poses;
  for (double tx : {-0.25, 0.0, 0.25})
    for (double ty : {-0.15, 0.15})
      for (double tz : {-0.1, 0.3})
        poses.push_back(eye_pose({tx, ty, tz}, -0.4 * tx - 0.05 * ty, 0.5 * ty + 0.02 * tx));
  std::size_t measured = 0;
  Largest video_truth{"largest_video_vs_truth_px"}, video_opencv{"largest_video_vs_opencv_px"};
  for (const Pose& P : poses) {
    const hd::core::ViewSetup s = setup_for(P, kD_m, kD_m);
    const auto dots = measure_dots(compositor_, frame_, P, kD_m, kD_m, nullptr);
    EXPECT_GE(dots.size(), 12u) << "most dots must be seen from pose at " << P.t.transpose();
    for (const auto& d : dots) {
      const auto E = hd::core::reprojection_error(s, d.X_world);
      ASSERT_TRUE(E.has_value());
      EXPECT_LT(*E, 1e-9) << "core: a point on the plane z_c = d has E = 0";
      video_truth.add((d.video_px - d.truth_px).norm());
      video_opencv.add((d.video_px - d.opencv_px).norm());
      EXPECT_LT((d.video_px - d.truth_px).norm(), kTruth_px)
          << "dot at " << d.X_world.transpose() << " eye at " << P.t.transpose();
      EXPECT_LT((d.video_px - d.opencv_px).norm(), kOpenCv_px)
          << "dot at " << d.X_world.transpose() << " eye at " << P.t.transpose();
    }
    measured += dots.size();
  }
  EXPECT_GE(measured, 250u);
}

TEST_F(Truthfulness, PlaneOffDShiftsEachDotByCoreE) {
  // Eyes near the camera (coverage 1, every dot seen), video projected too near or too far.
  std::vector<Pose> poses;
  for (double tx : {-0.08, 0.08})
    for (double ty : {-0.05, 0.06}) poses.push_back(eye_pose({tx, ty, -0.05}, -0.4 * tx, 0.4 * ty));
  poses.push_back(eye_pose({0.0, 0.0, 0.03}, 0.02, -0.03));
  Largest largest_E{"largest_E_px"}, shift_E{"largest_shift_vs_E_px"},
      max_m{"largest_max_shift_vs_m_px"}, video_opencv{"largest_video_vs_opencv_px"};
  for (double d_m : {0.7, 1.5}) {
    for (const Pose& P : poses) {
      const hd::core::ViewSetup s = setup_for(P, d_m, kD_m);
      hd::core::ViewMeasure vm{};
      const auto dots = measure_dots(compositor_, frame_, P, d_m, kD_m, &vm);
      ASSERT_EQ(dots.size(), static_cast<std::size_t>(kCols * kRows))
          << "every dot must be seen, d = " << d_m << " eye at " << P.t.transpose();
      double max_shift = 0.0;
      for (const auto& d : dots) {
        const auto E = hd::core::reprojection_error(s, d.X_world);
        ASSERT_TRUE(E.has_value());
        const double shift = (d.video_px - d.truth_px).norm();
        EXPECT_NEAR(shift, *E, kTruth_px) << "dot at " << d.X_world.transpose() << ", d = " << d_m;
        EXPECT_LT((d.video_px - d.opencv_px).norm(), kOpenCv_px)
            << "dot at " << d.X_world.transpose() << ", d = " << d_m;
        shift_E.add(std::abs(shift - *E));
        video_opencv.add((d.video_px - d.opencv_px).norm());
        max_shift = std::max(max_shift, shift);
        largest_E.add(*E);
      }
      EXPECT_GT(max_shift, 2.0) << "the shift must be large enough to mean something";
      // W is the dot rectangle (all of it in view), the video covers the whole eye picture, so
      // m = E_max / 1 is core's largest error over what is seen.
      EXPECT_NEAR(vm.coverage, 1.0, 1e-9);
      EXPECT_NEAR(max_shift, vm.m, kTruth_px) << "d = " << d_m << " eye at " << P.t.transpose();
      max_m.add(std::abs(max_shift - vm.m));
    }
  }
  EXPECT_GT(largest_E.value, 15.0);
}

TEST_F(Truthfulness, TheReferencesAgreeWithEachOther) {
  // The references on their own, no compositor. The frame: the camera faces the plane squarely,
  // so each dot is a round Gaussian centred exactly on its projection u = f x / D + c_x; this pins
  // the analytic drawing's pixel convention (a half-pixel slip would move every dot by 0.5 px).
  Largest frame_dot{"largest_frame_dot_vs_projection_px"}, opencv_E{"largest_opencv_shift_vs_E_px"};
  for (const auto& Xc : dots_camera(kD_m)) {
    const Eigen::Vector2d expect(kReal.fx * Xc.x() / Xc.z() + kReal.cx,
                                 kReal.fy * Xc.y() / Xc.z() + kReal.cy);
    const auto c = centroid(frame_, expect);
    ASSERT_TRUE(c.has_value());
    EXPECT_LT((*c - expect).norm(), 0.001) << "dot at " << Xc.transpose();
    frame_dot.add((*c - expect).norm());
  }
  // OpenCV's warp of that frame with the test's homography shows the plane at d = D where the
  // analytic drawing from the eye does, and its dots move by core's E off d.
  const Pose P = eye_pose({0.08, -0.05, -0.05}, -0.03, -0.02);
  for (double d_m : {0.7, 1.0, 1.5}) {
    const hd::core::ViewSetup s = setup_for(P, d_m, kD_m);
    const ImageRgba8 truth = truth_picture(P, kD_m);
    const ImageRgba8 opencv = opencv_picture(frame_, P, d_m);
    for (const auto& Xc : dots_camera(kD_m)) {
      const Eigen::Vector3d X = kTWorldReal.to_world(Xc);
      const auto ct = centroid(truth, kEye.project(P.to_camera(X)));
      const auto co =
          centroid(opencv, kEye.project(P.to_camera(kTWorldReal.to_world(Xc * (d_m / kD_m)))));
      ASSERT_TRUE(ct && co) << "d = " << d_m;
      const auto E = hd::core::reprojection_error(s, X);
      ASSERT_TRUE(E.has_value());
      EXPECT_NEAR((*co - *ct).norm(), *E, kTruth_px) << "dot at " << X.transpose();
      opencv_E.add(std::abs((*co - *ct).norm() - *E));
    }
  }
}

TEST_F(Truthfulness, CentroidFindsAKnownSubPixelShift) {
  // The measuring method on its own: the analytic drawing of the plane moved by a known amount
  // along the camera x axis shifts every dot by f * dx / z in the image (a pure translation
  // parallel to the plane is a pure image shift), which the centroid must recover.
  const Pose P0 = eye_pose({0.0, 0.0, 0.0}, 0.0, 0.0);
  const double dx_m = 0.0003;  // 0.135 px at f = 450, z = 1.0 m
  Pose P1 = P0;
  P1.t.x() -= dx_m;  // eye moves left, the picture moves right
  const ImageRgba8 a = truth_picture(P0, kD_m);
  const ImageRgba8 b = truth_picture(P1, kD_m);
  Largest error{"largest_error_px"};
  for (const auto& Xc : dots_camera(kD_m)) {
    const Eigen::Vector3d Xe = P0.to_camera(kTWorldReal.to_world(Xc));
    const auto ca = centroid(a, kEye.project(Xe));
    const auto cb = centroid(b, kEye.project(Xe));
    ASSERT_TRUE(ca && cb);
    const double expect_px = kEye.fx * dx_m / Xe.z();
    EXPECT_NEAR((*cb - *ca).x(), expect_px, 0.02);
    EXPECT_NEAR((*cb - *ca).y(), 0.0, 0.02);
    error.add(std::max(std::abs((*cb - *ca).x() - expect_px), std::abs((*cb - *ca).y())));
  }
}

}  // namespace
