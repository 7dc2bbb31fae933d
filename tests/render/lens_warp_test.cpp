// The panel -> eye-image mapping against the lens polynomial's closed form, per channel.
#include <gtest/gtest.h>

#include <cmath>

#include "render/lens/hmd_profile_file.h"
#include "render/lens/lens_warp.h"
#include "test_paths.h"

namespace hd::render::lens {
namespace {

const std::string kDir = std::string(hd::test::source_dir()) + "/render/lens/profiles/";
constexpr double kPi = 3.14159265358979323846;

// OpenHMD's DK1 numbers, written out here independently of the file.
constexpr double kA = 1.003, kB = -1.005, kC = 0.403, kD = 0.599;
constexpr double kUnit = 0.07488 - 0.03175;  // m
constexpr double kPitch = 0.14976 / 1280;    // m per panel pixel
double dk1_source_radius(double r) {
  return r * (kA * r * r * r + kB * r * r + kC * r + kD);
}

TEST(LensWarp, PanelPixelSamplesThePolynomialsRadiusPerChannel) {
  const LensWarp w(load_hmd_profile(kDir + "oculus-dk1.yaml"));
  const double scale[3] = {0.985, 1.0, 1.015};
  const double eye_pitch = kD * kPitch;  // one eye pixel per panel pixel at the centre (green)
  for (int e = 0; e < 2; ++e) {
    const double lc_x = e == 0 ? kUnit : 0.03175;
    // Along the row through the lens centre (y = 0.0468 m = 400 px) and along a diagonal.
    for (double x_px = 2.5; x_px < 640; x_px += 37.0) {
      for (int c = 0; c < 3; ++c) {
        double u = 0, v = 0;
        const double q = x_px * kPitch - lc_x;
        const double r = std::abs(q) / kUnit;
        if (!w.source(e, x_px, 400.0, c, &u, &v)) {
          EXPECT_GT(r, 1.15);
          continue;
        }
        const double expect = std::copysign(scale[c] * dk1_source_radius(r) * kUnit, q) / eye_pitch;
        EXPECT_NEAR(u - w.eye(e).cx, expect, 0.01) << "eye " << e << " x " << x_px << " c " << c;
        EXPECT_NEAR(v - w.eye(e).cy, 0.0, 1e-9);
      }
    }
    for (double t = -180; t <= 180; t += 23.0) {
      const double x_px = lc_x / kPitch + t, y_px = 400.0 + 0.8 * t;
      const double qx = t * kPitch, qy = 0.8 * t * kPitch;
      const double r = std::hypot(qx, qy) / kUnit;
      for (int c = 0; c < 3; ++c) {
        double u = 0, v = 0;
        ASSERT_TRUE(w.source(e, x_px, y_px, c, &u, &v));
        const double rs = r > 0 ? scale[c] * dk1_source_radius(r) / r : scale[c] * kD;
        EXPECT_NEAR(u - w.eye(e).cx, rs * qx / eye_pitch, 0.01);
        EXPECT_NEAR(v - w.eye(e).cy, rs * qy / eye_pitch, 0.01);
      }
    }
  }
}

TEST(LensWarp, CentreKeepsOneEyePixelPerPanelPixel) {
  const LensWarp w(load_hmd_profile(kDir + "oculus-dk1.yaml"));
  const double x0 = kUnit / kPitch;
  double u0 = 0, u1 = 0, v = 0;
  // Over a tenth of a pixel each side of the centre (P's curvature stays below 1e-4 there).
  ASSERT_TRUE(w.source(0, x0 - 0.05, 400.0, 1, &u0, &v));
  ASSERT_TRUE(w.source(0, x0 + 0.05, 400.0, 1, &u1, &v));
  EXPECT_NEAR((u1 - u0) / 0.1, 1.0, 1e-4);
}

TEST(LensWarp, EyeImageHoldsEverySampleOfEveryChannel) {
  for (const char* name : {"oculus-dk1.yaml", "osvr-hdk-1.3.yaml"}) {
    const LensWarp w(load_hmd_profile(kDir + name));
    double min_u = 1e9, max_u = -1e9, min_v = 1e9, max_v = -1e9;
    for (int e = 0; e < 2; ++e)
      for (int y = 0; y < w.panel_height(); y += 3)
        for (int x = 0; x < w.eye_panel_width(); x += 3)
          for (int c = 0; c < 3; ++c) {
            double u = 0, v = 0;
            if (!w.source(e, x + 0.5, y + 0.5, c, &u, &v)) continue;
            min_u = std::min(min_u, u), max_u = std::max(max_u, u);
            min_v = std::min(min_v, v), max_v = std::max(max_v, v);
          }
    EXPECT_GE(min_u, 0.5) << name;
    EXPECT_GE(min_v, 0.5) << name;
    EXPECT_LE(max_u, w.eye_width() - 0.5) << name;
    EXPECT_LE(max_v, w.eye_height() - 0.5) << name;
    EXPECT_LT(max_u - min_u, w.eye_width() - 1.0 + 3.0) << name;  // and not much larger
  }
}

TEST(LensWarp, PublishedFieldOfViewSpansTheUndistortedHalfPanel) {
  const LensWarp w(load_hmd_profile(kDir + "osvr-hdk-1.3.yaml"));
  // The undistorted half panel: q_src from -0.471 to +0.529 of 0.06088 m horizontally; at the
  // centre one eye pixel is one panel pixel (0.06088 / 960 m).
  const double pitch = 0.06088 / 960;
  const core::Pinhole& k = w.eye(0);
  const double fov_x =
      std::atan(0.471 * 0.06088 / pitch / k.fx) + std::atan(0.529 * 0.06088 / pitch / k.fx);
  EXPECT_NEAR(fov_x * 180 / kPi, 90.0, 1e-6);
  const double fov_y = 2 * std::atan(0.5 * 0.06849 / (0.06849 / 1080) / k.fy);
  EXPECT_NEAR(fov_y * 180 / kPi, 96.73, 1e-6);
  // The eye image the lens needs is wider than the undistorted half (its corners are pulled in).
  EXPECT_GT(w.eye_fov_x_deg(), 90.0);
  EXPECT_LT(w.eye_fov_x_deg(), 180.0);
}

}  // namespace
}  // namespace hd::render::lens
