// E, E_max, coverage, m and the update region against closed forms, and every hard case of
// DESIGN.md "Principles" with its exact expected result.
//
// Closed form used throughout: for a virtual camera translated laterally by b with the same
// orientation as the real one, a point at depth Z maps to x'' = x d / Z on the plane, so
//   E = |f (x - b)/Z - f (x d/Z - b)/d| = f b |1/Z - 1/d|   for every x, y.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/coverage.h"
#include "core/plane_homography.h"
#include "core/reprojection_error.h"
#include "core/update_region.h"
#include "core/view_measure.h"
#include "setups.h"

using namespace hd::core;
using hd::core::test::example_setup;
using hd::core::test::pinhole;
using hd::core::test::raster_coverage;
using hd::core::test::rot;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

void expect_region(const ViewMeasure& vm, double u0, double v0, double u1, double v1,
                   double tol = 1e-9) {
  ASSERT_TRUE(vm.has_region);
  EXPECT_NEAR(vm.region.u_min, u0, tol);
  EXPECT_NEAR(vm.region.v_min, v0, tol);
  EXPECT_NEAR(vm.region.u_max, u1, tol);
  EXPECT_NEAR(vm.region.v_max, v1, tol);
}
}  // namespace

TEST(ClosedForm, IssueExample) {
  const ViewSetup s = example_setup();
  EXPECT_NEAR(*reprojection_error(s, {0, 0, 1.0}), 20.0, 1e-9);
  const ViewMeasure vm = measure_view(s);
  EXPECT_NEAR(vm.e_max_px, 60.0, 1e-9);   // 1000 * 0.02 * |1/0.2 - 1/0.5|
  EXPECT_NEAR(vm.coverage, 0.95, 1e-12);  // quad spans u in [-40, 760] of [0, 800]
  EXPECT_NEAR(vm.m, 60.0 / 0.95, 1e-9);
  expect_region(vm, 80, 0, 1600, 1200);
}

TEST(ClosedForm, LateralTranslationOnAxis) {
  for (double b : {0.005, 0.02, -0.1}) {
    for (double f : {300.0, 1000.0, 5000.0}) {
      for (double d : {0.3, 0.5, 2.0}) {
        ViewSetup s = example_setup();
        s.virt = pinhole(f, 800, 600);
        s.T_world_virt.t = {b, 0, 0};
        s.d_m = d;
        for (double Z : {0.2, 0.5, 0.77, 1.0, 3.0}) {
          const auto e = reprojection_error(s, {0, 0, Z});
          ASSERT_TRUE(e.has_value());
          EXPECT_NEAR(*e, f * std::abs(b) * std::abs(1 / Z - 1 / d), 1e-9 * f) << b << " " << Z;
        }
      }
    }
  }
}

TEST(ClosedForm, LateralTranslationEmaxIsAtTheNearestDepth) {
  // W spans depths 0.2..1.0; E depends on depth only, so E_max = f b max(|1/0.2-1/d|, |1-1/d|).
  for (double d : {0.25, 0.5, 0.9, 5.0}) {
    ViewSetup s = example_setup();
    s.d_m = d;
    const double expected = 1000 * 0.02 * std::max(std::abs(5 - 1 / d), std::abs(1 - 1 / d));
    EXPECT_NEAR(measure_view(s).e_max_px, expected, 1e-9 * expected + 1e-12) << d;
  }
}

TEST(ClosedForm, PureRotationHasNoError) {
  ViewSetup s = example_setup();
  s.T_world_virt.t = s.T_world_real.t;
  s.T_world_virt.R = rot(0.3, -0.2, 0.1);
  for (const Eigen::Vector3d& X : {Eigen::Vector3d(0.1, 0.05, 0.8), Eigen::Vector3d(0.3, 0, 0.9),
                                   Eigen::Vector3d(0.2, -0.1, 0.3)}) {
    const auto e = reprojection_error(s, X);
    ASSERT_TRUE(e.has_value());
    EXPECT_NEAR(*e, 0.0, 1e-9);
  }
  EXPECT_NEAR(measure_view(s).e_max_px, 0.0, 1e-9);
}

TEST(ClosedForm, PointsOnThePlaneHaveNoError) {
  ViewSetup s = example_setup();
  s.T_world_real = {rot(0.1, 0.05, 0.02), {0.01, -0.02, 0.03}};
  s.T_world_virt = {rot(-0.15, 0.1, 0.0), {0.05, 0.02, -0.04}};
  for (double x : {-0.1, 0.0, 0.15})
    for (double y : {-0.1, 0.07}) {
      const Eigen::Vector3d X = s.T_world_real.to_world({x, y, s.d_m});
      const auto e = reprojection_error(s, X);
      ASSERT_TRUE(e.has_value());
      EXPECT_NEAR(*e, 0.0, 1e-9);
    }
}

TEST(ClosedForm, IdenticalCamerasCoverEverythingAndUploadTheWholeImage) {
  ViewSetup s;
  s.real = s.virt = pinhole(1000, 640, 480);
  s.T_world_real = s.T_world_virt = {rot(0.2, 0.1, 0.3), {0.1, 0.2, 0.3}};
  s.d_m = 0.7;
  s.workspace = {{-1, -1, -1}, {1, 1, 1}};
  const ViewMeasure vm = measure_view(s);
  EXPECT_NEAR(vm.coverage, 1.0, 1e-12);
  EXPECT_NEAR(vm.e_max_px, 0.0, 1e-9);
  EXPECT_NEAR(vm.m, 0.0, 1e-9);
  expect_region(vm, 0, 0, 640, 480);
}

TEST(ClosedForm, ParallelPlanesAxialTranslation) {
  // Virtual 0.5 m behind the real camera, same orientation: the quad at z_o = 1 spans
  // u in [200,600], v in [150,450] -> C = 0.25; the virtual frustum there covers the whole quad.
  ViewSetup s = example_setup();
  s.T_world_virt.t = {0, 0, -0.5};
  const ViewMeasure vm = measure_view(s);
  EXPECT_NEAR(vm.coverage, 0.25, 1e-12);
  expect_region(vm, 0, 0, 1600, 1200);
  EXPECT_NEAR(*reprojection_error(s, {0, 0, 0.9}), 0.0, 1e-9);  // on the common axis
  // Off axis: x'' = x d/Z at z_o = 1 vs x at z_o = Z + 0.5: E = f |x| |1/(Z+0.5) - (d/Z)/1|.
  const double x = 0.1, Z = 0.8;
  EXPECT_NEAR(*reprojection_error(s, {x, 0, Z}), 1000 * x * std::abs(1 / (Z + 0.5) - 0.5 / Z),
              1e-9);
}

TEST(ClosedForm, HomographyMapsVirtualPixelsThroughThePlane) {
  ViewSetup s = example_setup();
  s.T_world_real = {rot(0.1, 0.05, 0.02), {0.01, -0.02, 0.03}};
  s.T_world_virt = {rot(-0.15, 0.1, 0.0), {0.05, 0.02, -0.04}};
  const Eigen::Matrix3d H = virtual_to_real_homography(s);
  for (double x : {-0.1, 0.0, 0.12}) {
    const Eigen::Vector3d Xr(x, 0.05, s.d_m);  // on the plane, real frame
    const Eigen::Vector3d Xw = s.T_world_real.to_world(Xr);
    const Eigen::Vector2d pv = s.virt.project(s.T_world_virt.to_camera(Xw));
    const Eigen::Vector3d h = H * Eigen::Vector3d(pv.x(), pv.y(), 1.0);
    ASSERT_GT(h.z(), 0.0);
    const Eigen::Vector2d pr = s.real.project(Xr);
    EXPECT_NEAR(h.x() / h.z(), pr.x(), 1e-8);
    EXPECT_NEAR(h.y() / h.z(), pr.y(), 1e-8);
  }
}

// ---- Hard cases (DESIGN.md "Principles") ----

TEST(HardCase, VirtualCameraBehindThePlane) {
  // Virtual at z = 0.6 > d = 0.5 looking the same way: X'' (z_o = -0.1) is never in front of it.
  ViewSetup s = example_setup();
  s.T_world_virt.t = {0, 0, 0.6};
  s.workspace = {{-0.5, -0.5, 0.7}, {0.5, 0.5, 1.0}};
  EXPECT_EQ(*reprojection_error(s, {0, 0, 0.9}), kInf);
  const ViewMeasure vm = measure_view(s);
  EXPECT_EQ(vm.e_max_px, kInf);
  EXPECT_EQ(vm.coverage, 0.0);
  EXPECT_EQ(vm.m, kInf);
  EXPECT_FALSE(vm.has_region);
  EXPECT_GT(virtual_to_real_homography(s)(2, 2), -1e300);  // finite, no NaN
  EXPECT_TRUE(virtual_to_real_homography(s).allFinite());
}

TEST(HardCase, VirtualCameraOnThePlaneLookingAlongIt) {
  // Virtual centre on z_c = d, optical axis along +x (columns of R: x_o=(0,0,-1), y_o=(0,1,0),
  // z_o=(1,0,0)). The plane is seen edge-on: every quad point has x_o = 0, so C = 0 exactly and
  // m = inf; DESIGN 1's clip still leaves the sliver z_o = x in [0.01, 0.2], |y| <= 0.3 x
  // (v-bounds of the virtual frustum), whose real-image box is u = 4000x+800, v = 4000y+600.
  ViewSetup s = example_setup();
  s.T_world_virt.R << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  s.T_world_virt.t = {0, 0, 0.5};
  const ViewMeasure vm = measure_view(s);
  EXPECT_EQ(vm.coverage, 0.0);
  EXPECT_EQ(vm.m, kInf);
  expect_region(vm, 840, 360, 1600, 840, 1e-6);
}

TEST(HardCase, GrazingViewMatchesRaster) {
  // Virtual yawed 80 degrees: the plane is seen at a grazing angle. No closed form; the analytic
  // coverage must agree with a fine raster count.
  ViewSetup s = example_setup();
  s.T_world_virt = {rot(80 * M_PI / 180, 0, 0), {-0.3, 0, 0.45}};
  const double c = coverage(s);
  const double r = raster_coverage(s, 1.0);
  EXPECT_GT(c, 0.0);
  EXPECT_NEAR(c, r, 0.01);
}

TEST(HardCase, EmptyObservationSpace) {
  // Workspace entirely behind both cameras: W is empty, E_max = 0, so m = 0 / C = 0.
  ViewSetup s = example_setup();
  s.workspace = {{-0.5, -0.5, -1.0}, {0.5, 0.5, -0.5}};
  const ViewMeasure vm = measure_view(s);
  EXPECT_EQ(vm.e_max_px, 0.0);
  EXPECT_NEAR(vm.coverage, 0.95, 1e-12);
  EXPECT_EQ(vm.m, 0.0);
  expect_region(vm, 80, 0, 1600, 1200);
}

TEST(HardCase, FlatWorkspaces) {
  // Zero-thickness box at Z = 1: every point has E = 1000 * 0.02 * |1 - 2| = 20.
  ViewSetup s = example_setup();
  s.workspace = {{-0.5, -0.5, 1.0}, {0.5, 0.5, 1.0}};
  EXPECT_NEAR(measure_view(s).e_max_px, 20.0, 1e-9);
  // Zero-thickness in x (a wall at x = 0.05 inside the virtual frustum): depths 0.2..1 remain.
  s.workspace = {{0.05, -0.5, 0.2}, {0.05, 0.5, 1.0}};
  EXPECT_NEAR(measure_view(s).e_max_px, 60.0, 1e-9);
  // A degenerate point box at (0,0,0.4): E = 1000*0.02*|2.5 - 2| = 10.
  s.workspace = {{0, 0, 0.4}, {0, 0, 0.4}};
  EXPECT_NEAR(measure_view(s).e_max_px, 10.0, 1e-9);
}

TEST(HardCase, HugeD) {
  ViewSetup s = example_setup();
  s.d_m = 1e9;
  // E = f b |1/Z - 1e-9|: E_max at Z = 0.2 -> 20 * (5 - 1e-9).
  EXPECT_NEAR(measure_view(s).e_max_px, 20 * (5 - 1e-9), 1e-6);
  EXPECT_NEAR(*reprojection_error(s, {0.1, 0.1, 1.0}), 20 * (1 - 1e-9), 1e-6);
  // At z = 1e9 the quad spans x in [-4e8, 4e8] and the virtual frustum [0.02-4e8, 0.02+4e8]:
  // only a 0.02 m sliver of 8e8 m is uncovered.
  EXPECT_NEAR(coverage(s), 1.0 - 0.02 / 8e8, 1e-14);
}

TEST(HardCase, TinyDBelowNear) {
  // d = 1e-6 < near: X'' lies at z_o = 1e-6 <= near, never in front of the virtual camera.
  ViewSetup s = example_setup();
  s.d_m = 1e-6;
  EXPECT_EQ(*reprojection_error(s, {0, 0, 0.5}), kInf);
  const ViewMeasure vm = measure_view(s);
  EXPECT_EQ(vm.e_max_px, kInf);
  EXPECT_EQ(vm.coverage, 0.0);
  EXPECT_EQ(vm.m, kInf);
  EXPECT_FALSE(vm.has_region);
}

TEST(HardCase, TinyDAboveNear) {
  // d = 0.02 (just beyond near): closed form still holds, E_max at Z = 1: 20 * |1 - 50| = 980.
  ViewSetup s = example_setup();
  s.d_m = 0.02;
  EXPECT_NEAR(measure_view(s).e_max_px, 1000 * 0.02 * 49, 1e-7);
}

TEST(HardCase, ExtremeFocalLengths) {
  ViewSetup s = example_setup();
  s.virt = pinhole(1e6, 800, 600);  // 0.05 degree field of view
  EXPECT_NEAR(measure_view(s).e_max_px, 1e6 * 0.02 * 3, 1e-9 * 6e4);
  // The quad is 0.4 m x 0.3 m at 0.5 m: seen with f = 1e6 it covers the whole screen.
  EXPECT_NEAR(coverage(s), 1.0, 1e-12);
  s.virt = pinhole(1e-3, 800, 600);  // nearly 180 degrees
  EXPECT_NEAR(measure_view(s).e_max_px, 1e-3 * 0.02 * 3, 1e-12 * 6e-5);
  // The quad projects to 0.8 f x 0.6 f pixels: C = 0.48 f^2 / (800 * 600).
  EXPECT_NEAR(coverage(s), 0.48e-6 / 480000.0, 1e-9 * 1e-12);
  s.real = pinhole(1e6, 1600, 1200);  // a real telephoto: quad 0.0008 x 0.0006 m at 0.5 m
  s.virt = pinhole(1000, 800, 600);
  const double side_u = 1000 * 0.0008 / 0.5, side_v = 1000 * 0.0006 / 0.5;
  EXPECT_NEAR(coverage(s), side_u * side_v / 480000.0, 1e-12);
}

TEST(HardCase, NanAndInvalidInputNeverEscape) {
  auto check_unusable = [](const ViewSetup& s) {
    const ViewMeasure vm = measure_view(s);
    EXPECT_EQ(vm.e_max_px, kInf);
    EXPECT_EQ(vm.coverage, 0.0);
    EXPECT_EQ(vm.m, kInf);
    EXPECT_FALSE(vm.has_region);
    EXPECT_FALSE(reprojection_error(s, {0, 0, 1}).has_value());
    EXPECT_FALSE(update_region(s).has_value());
    EXPECT_TRUE(virtual_to_real_homography(s).isZero());
  };
  ViewSetup s = example_setup();
  s.real.fx = NAN;
  check_unusable(s);
  s = example_setup();
  s.virt.cy = NAN;
  check_unusable(s);
  s = example_setup();
  s.T_world_virt.t.x() = NAN;
  check_unusable(s);
  s = example_setup();
  s.T_world_real.R(0, 1) = 0.5;  // not a rotation
  check_unusable(s);
  s = example_setup();
  s.d_m = NAN;
  check_unusable(s);
  s = example_setup();
  s.d_m = 0.0;
  check_unusable(s);
  s = example_setup();
  s.near_m = -1;
  check_unusable(s);
  s = example_setup();
  s.workspace.min_m.z() = 2.0;  // min > max
  check_unusable(s);
  s = example_setup();
  s.virt.width = 0;
  check_unusable(s);
  s = example_setup();
  EXPECT_FALSE(reprojection_error(s, {NAN, 0, 1}).has_value());
  EXPECT_FALSE(reprojection_error(s, {0, 0, INFINITY}).has_value());
}

TEST(HardCase, PointsBehindEitherCameraAreUndefined) {
  const ViewSetup s = example_setup();
  EXPECT_FALSE(reprojection_error(s, {0, 0, -1}).has_value());
  EXPECT_FALSE(reprojection_error(s, {0, 0, 0.01}).has_value());  // exactly at near
  // In front of the real camera, behind the virtual one (virtual looking back).
  ViewSetup t = example_setup();
  t.T_world_virt.R = rot(M_PI, 0, 0);
  EXPECT_FALSE(reprojection_error(t, {0, 0, 1}).has_value());
}
