// Stereo: eye poses are the head pose offset by -/+ IPD/2 along the head x axis, and both eyes
// show the same variant because the decision uses the worse eye's m.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "core/transition.h"
#include "core/view_measure.h"
#include "render/stereo/stereo_rig.h"

namespace hd::render {
namespace {

StereoRig rig() {
  StereoRig r;
  r.ipd_m = 0.064;
  r.eye[0] = {450, 450, 330, 300, 640, 600};
  r.eye[1] = {450, 450, 310, 300, 640, 600};
  return r;
}

RC_GTEST_PROP(StereoRig, EyesAreOffsetAlongTheHeadXAxis, ()) {
  auto unit = [] { return *rc::gen::inRange(-1000, 1001) / 1000.0; };
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(unit(), unit(), unit(), unit() + 2.0).normalized();
  const core::Pose head = core::Pose::from(q, Eigen::Vector3d(unit(), unit(), unit()));
  const StereoRig r = rig();
  const core::Pose L = r.T_world_eye(head, 0), R = r.T_world_eye(head, 1);
  const Eigen::Vector3d x_axis = q.toRotationMatrix().col(0);
  RC_ASSERT((R.t - L.t - r.ipd_m * x_axis).norm() < 1e-12);
  RC_ASSERT(((L.t + R.t) / 2 - head.t).norm() < 1e-12);
  RC_ASSERT((L.R - head.R).norm() < 1e-12);
  RC_ASSERT((R.R - head.R).norm() < 1e-12);
}

TEST(StereoRig, SideBySideViewportsAndMonitorCase) {
  const StereoRig r = rig();
  EXPECT_EQ(r.viewport(0).x, 0);
  EXPECT_EQ(r.viewport(1).x, 640);
  EXPECT_EQ(r.output_width(), 1280);
  const StereoRig mono = StereoRig::monitor(r.eye[0]);
  EXPECT_EQ(mono.eye_count(), 1);
  const core::Pose head = core::Pose::from(Eigen::Quaterniond(0.9, 0.1, 0.3, 0.2), {1, 2, 3});
  EXPECT_TRUE(mono.T_world_eye(head, 0).t.isApprox(head.t));
  EXPECT_EQ(mono.output_width(), 640);
  EXPECT_TRUE(r.valid());
  StereoRig bad = r;
  bad.ipd_m = NAN;
  EXPECT_FALSE(bad.valid());
}

TEST(StereoRig, WorseEyeDecidesSoBothEyesShowTheSameVariant) {
  // The real camera sits exactly where the left eye is, with the left eye's intrinsics: the
  // left eye alone would see perfect video (m = 0); the right eye is 64 mm away (m > 0).
  const StereoRig r = rig();
  const core::Pose head = core::Pose::identity();
  core::ViewSetup base;
  base.real = r.eye[0];
  base.T_world_real = r.T_world_eye(head, 0);
  base.d_m = 0.8;
  base.near_m = 0.05;
  base.workspace.min_m = {-1.0, -1.0, 0.3};
  base.workspace.max_m = {1.0, 1.0, 3.0};
  double m[2];
  for (int i = 0; i < 2; ++i) {
    core::ViewSetup s = base;
    s.virt = r.eye[i];
    s.T_world_virt = r.T_world_eye(head, i);
    m[i] = core::measure_view(s).m;
  }
  ASSERT_NEAR(m[0], 0.0, 1e-9);
  ASSERT_GT(m[1], 1.0);
  core::TransitionParams tp;
  tp.mode = core::TransitionMode::kAbrupt;
  tp.m_t = m[1] / 2;  // between the eyes: the left eye alone would say video
  tp.hysteresis = 0.0;
  core::Transition left_alone(tp), shared(tp);
  EXPECT_EQ(left_alone.update(m[0], 0.011).variant, core::Variant::kVideo);
  const core::TransitionState both = shared.update(StereoRig::worse_m(m[0], m[1]), 0.011);
  EXPECT_EQ(both.variant, core::Variant::kSynthetic);
  EXPECT_EQ(StereoRig::worse_m(m[0], NAN), INFINITY);
  EXPECT_EQ(StereoRig::worse_m(m[0], m[1]), m[1]);
}

}  // namespace
}  // namespace hd::render
