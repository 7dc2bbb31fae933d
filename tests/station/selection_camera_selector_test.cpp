// Camera choice: lowest m wins, with hysteresis (margin + dwell), and guidance toward the nearest
// camera pose, against closed-form setups.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/view_measure.h"
#include "render/overlay/guidance_cue.h"
#include "station/selection/camera_selector.h"

namespace hd::station {
namespace {

constexpr double kInf = INFINITY;

TEST(SelectionCameraSelector, PicksTheLowestOnTheFirstFrame) {
  CameraSelector s;
  const double m[] = {12.0, 3.0, 7.0};
  EXPECT_EQ(s.update(m, 0.011), 1);
}

TEST(SelectionCameraSelector, NoFiniteCameraGivesMinusOne) {
  CameraSelector s;
  const double m[] = {kInf, NAN};
  EXPECT_EQ(s.update(m, 0.011), -1);
  EXPECT_EQ(s.update(std::span<const double>{}, 0.011), -1);
}

TEST(SelectionCameraSelector, SmallAlternatingDifferencesDoNotFlicker) {
  CameraSelector s({0.2, 0.25});
  for (int i = 0; i < 200; ++i) {
    // Camera 1 is alternately 10 % better and 10 % worse: inside the margin, never a switch.
    const double m[] = {10.0, i % 2 ? 9.0 : 11.0};
    EXPECT_EQ(s.update(m, 1.0 / 90), 0) << i;
  }
  EXPECT_EQ(s.switches(), 1u);  // the initial choice only
}

TEST(SelectionCameraSelector, SwitchesOnlyAfterTheDwellTime) {
  SelectionParams p{0.2, 0.25};
  CameraSelector s(p);
  const double first[] = {10.0, 20.0};
  ASSERT_EQ(s.update(first, 0.01), 0);
  const double better[] = {10.0, 5.0};
  // 0.01 s frames: the 25th frame brings the accumulated time to 0.25 s.
  for (int i = 1; i <= 24; ++i) ASSERT_EQ(s.update(better, 0.01), 0) << i;
  EXPECT_EQ(s.update(better, 0.01), 1);
  // An interruption restarts the dwell.
  CameraSelector t(p);
  ASSERT_EQ(t.update(first, 0.01), 0);
  for (int i = 0; i < 20; ++i) t.update(better, 0.01);
  t.update(first, 0.01);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(t.update(better, 0.01), 0);
}

TEST(SelectionCameraSelector, LeavesAnUnusableCameraAtOnce) {
  CameraSelector s;
  const double a[] = {1.0, 50.0};
  ASSERT_EQ(s.update(a, 0.01), 0);
  const double b[] = {kInf, 50.0};
  EXPECT_EQ(s.update(b, 0.01), 1);
}

core::ViewSetup setup(const core::Pose& cam, const core::Pose& eye) {
  core::ViewSetup v;
  v.real = {500, 500, 320, 240, 640, 480};
  v.virt = v.real;
  v.T_world_real = cam;
  v.T_world_virt = eye;
  v.d_m = 1.5;
  v.near_m = 0.05;
  v.workspace.min_m = {-1.0, -1.0, 1.0};
  v.workspace.max_m = {1.0, 1.0, 2.0};
  return v;
}

TEST(SelectionCameraSelector, ColocatedCameraHasZeroErrorAndWins) {
  const core::Pose eye = core::Pose::identity();
  core::Pose offset;
  offset.t = {0.4, 0.0, 0.0};
  const double m[] = {core::measure_view(setup(offset, eye)).m,
                      core::measure_view(setup(eye, eye)).m};
  EXPECT_GT(m[0], 1.0);
  EXPECT_NEAR(m[1], 0.0, 1e-9);  // same pinhole, same pose: E = 0 everywhere, C = 1
  CameraSelector s;
  EXPECT_EQ(s.update(m, 0.011), 1);
}

render::GuidanceCamera cam_at(Eigen::Vector3d t, Eigen::Matrix3d R = Eigen::Matrix3d::Identity()) {
  render::GuidanceCamera c;
  c.p_c = {400, 400, 320, 240, 640, 480};
  c.T_world_real.R = R;
  c.T_world_real.t = t;
  c.d_m = 2.0;
  return c;
}

TEST(SelectionGuidance, PointsTowardTheNearestCameraInTheEyeImage) {
  const core::Pinhole eye{500, 500, 400, 300, 800, 600};
  const core::Pose T = core::Pose::identity();
  // Camera 1 m ahead and 0.5 m to the right: projects to u = 400 + 500 * 0.5 = 650, v = 300.
  const render::GuidanceCamera cams[] = {cam_at({3.0, 0.0, 0.0}), cam_at({0.5, 0.0, 1.0})};
  const render::GuidanceCue cue = render::guidance_toward_nearest(eye, T, cams);
  ASSERT_TRUE(cue.active);
  EXPECT_EQ(cue.camera, 1);
  EXPECT_NEAR(cue.distance_m, std::sqrt(1.25), 1e-12);
  EXPECT_TRUE(cue.target_in_front);
  EXPECT_NEAR(cue.target_px.x(), 650.0, 1e-9);
  EXPECT_NEAR(cue.target_px.y(), 300.0, 1e-9);
  EXPECT_NEAR(cue.direction_px.x(), 1.0, 1e-12);
  EXPECT_NEAR(cue.direction_px.y(), 0.0, 1e-12);
  // Ghost frustum: centre, then the top-left corner ray (-0.8, -0.6, 1) scaled to z = 2.
  EXPECT_TRUE(cue.frustum_world[0].isApprox(Eigen::Vector3d(0.5, 0, 1)));
  EXPECT_TRUE(cue.frustum_world[1].isApprox(Eigen::Vector3d(0.5 - 1.6, -1.2, 3.0)));
}

TEST(SelectionGuidance, CameraAboveMeansUpAndBehindMeansTurn) {
  const core::Pinhole eye{500, 500, 400, 300, 800, 600};
  const render::GuidanceCamera above[] = {cam_at({0.0, -0.5, 0.5})};  // y down: -y is up
  const render::GuidanceCue up =
      render::guidance_toward_nearest(eye, core::Pose::identity(), above);
  EXPECT_NEAR(up.direction_px.y(), -1.0, 1e-12);
  const render::GuidanceCamera behind_left[] = {cam_at({-1.0, 0.0, -1.0})};
  const render::GuidanceCue turn =
      render::guidance_toward_nearest(eye, core::Pose::identity(), behind_left);
  EXPECT_FALSE(turn.target_in_front);
  EXPECT_NEAR(turn.direction_px.x(), -1.0, 1e-12);
}

TEST(SelectionGuidance, SamePositionOtherOrientationPointsAlongTheRotation) {
  const core::Pinhole eye{500, 500, 400, 300, 800, 600};
  // The camera sits at the eye but is yawed 20 deg to the right (about +y down... i.e. -y up):
  // its view centre 2 m ahead is at x = 2 sin 20, z = 2 cos 20 in the eye frame.
  const double a = 20.0 * M_PI / 180.0;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const render::GuidanceCamera cams[] = {cam_at({0.0, 0.0, 0.0}, R)};
  const render::GuidanceCue cue =
      render::guidance_toward_nearest(eye, core::Pose::identity(), cams);
  EXPECT_NEAR(cue.rotation_rad, a, 1e-12);
  EXPECT_NEAR(cue.target_px.x(), 400 + 500 * std::tan(a), 1e-9);
  EXPECT_NEAR(cue.direction_px.x(), 1.0, 1e-12);
}

TEST(SelectionGuidance, NoCamerasNoCue) {
  const core::Pinhole eye{500, 500, 400, 300, 800, 600};
  EXPECT_FALSE(render::guidance_toward_nearest(eye, core::Pose::identity(), {}).active);
}

}  // namespace
}  // namespace hd::station
