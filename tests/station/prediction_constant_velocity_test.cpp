// Constant-velocity prediction against closed forms: constant rates are predicted exactly.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

#include "station/prediction/constant_velocity_predictor.h"
#include "station/prediction/pose_history.h"

namespace hd::station {
namespace {

// The closed form, written with Eigen's AngleAxis (not the predictor's so3 helpers).
Eigen::Quaterniond rotate_at(const Eigen::Quaterniond& q0, const Eigen::Vector3d& w, double t) {
  const double a = w.norm() * t;
  if (w.norm() == 0.0) return q0;
  return q0 * Eigen::Quaterniond(Eigen::AngleAxisd(a, w.normalized()));
}

drivers::PoseSample sample(const Eigen::Quaterniond& q, const Eigen::Vector3d& p, int64_t t_ns) {
  drivers::PoseSample s;
  s.T_tracker_head = core::Pose::from(q, p);
  s.has_position = true;
  s.host_timestamp_ns = t_ns;
  return s;
}

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

struct Motion {
  Eigen::Quaterniond q0;
  Eigen::Vector3d w_rad_s;
  Eigen::Vector3d p0_m;
  Eigen::Vector3d v_m_s;
};

void check_exact(const Motion& m, bool with_gyro, double tol_deg, double tol_m) {
  ConstantVelocityPredictor cv;
  PoseHistory history;
  const int64_t period_ns = 1'000'000;
  int64_t t_ns = 0;
  for (int i = 0; i < 50; ++i) {
    t_ns = 1'000'000'000 + i * period_ns;
    const double t_s = static_cast<double>(t_ns - 1'000'000'000) * 1e-9;
    auto s = sample(rotate_at(m.q0, m.w_rad_s, t_s), m.p0_m + m.v_m_s * t_s, t_ns);
    s.has_angular_velocity = with_gyro;
    s.angular_velocity_rad_s = m.w_rad_s;
    ASSERT_TRUE(history.add(s, &cv));
  }
  for (int h_ms = 0; h_ms <= 100; h_ms += 10) {
    const int64_t target = t_ns + int64_t{h_ms} * 1'000'000;
    const double t_s = static_cast<double>(target - 1'000'000'000) * 1e-9;
    const core::Pose got = cv.predict(target);
    EXPECT_LT(angle_deg(got.R, rotate_at(m.q0, m.w_rad_s, t_s).toRotationMatrix()), tol_deg)
        << "horizon " << h_ms << " ms";
    EXPECT_LT((got.t - (m.p0_m + m.v_m_s * t_s)).norm(), tol_m) << "horizon " << h_ms << " ms";
  }
}

TEST(PredictionConstantVelocity, ConstantRotationRateIsPredictedExactlyByDifferencing) {
  const Motion m{Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized())),
                 Eigen::Vector3d(0.5, -1.2, 0.8), Eigen::Vector3d(0.1, 1.5, -0.3),
                 Eigen::Vector3d(0.2, -0.1, 0.05)};
  check_exact(m, false, 1e-7, 1e-9);
}

TEST(PredictionConstantVelocity, ConstantRotationRateIsPredictedExactlyFromGyro) {
  const Motion m{Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 3.0, 0.0),
                 Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  check_exact(m, true, 1e-7, 1e-12);
}

TEST(PredictionConstantVelocity, StaticHeadPredictsTheLastPose) {
  ConstantVelocityPredictor cv;
  PoseHistory history;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()));
  const Eigen::Vector3d p(0.3, 0.2, 0.1);
  for (int i = 1; i <= 20; ++i) ASSERT_TRUE(history.add(sample(q, p, i * 2'000'000), &cv));
  for (int64_t target : {int64_t{40'000'000}, int64_t{90'000'000}, int64_t{1'000'000'000}}) {
    const core::Pose got = cv.predict(target);
    EXPECT_LT(angle_deg(got.R, q.toRotationMatrix()), 1e-9);
    EXPECT_LT((got.t - p).norm(), 1e-12);
  }
}

TEST(PredictionConstantVelocity, UsesTheRequestedTimestamp) {
  ConstantVelocityPredictor cv;
  PoseHistory history;
  for (int i = 0; i < 20; ++i) {
    const double t_s = i * 1e-3;
    ASSERT_TRUE(
        history.add(sample(Eigen::Quaterniond::Identity(), {t_s * 1.0, 0, 0}, i * 1'000'000), &cv));
  }
  // 1 m/s along x: 19 ms newest sample; 30 ms ahead is 0.049 m, 60 ms ahead 0.079 m.
  EXPECT_NEAR(cv.predict(49'000'000).t.x(), 0.049, 1e-12);
  EXPECT_NEAR(cv.predict(79'000'000).t.x(), 0.079, 1e-12);
}

TEST(PredictionConstantVelocity, BeforeAnySampleIsIdentityAndNotReady) {
  ConstantVelocityPredictor cv;
  EXPECT_FALSE(cv.ready());
  EXPECT_TRUE(cv.predict(123).R.isIdentity());
}

RC_GTEST_PROP(PredictionConstantVelocity, AnyConstantMotionIsExact, ()) {
  auto unit = [] { return *rc::gen::inRange(-1000, 1001) / 1000.0; };
  Motion m;
  m.q0 = Eigen::Quaterniond(unit(), unit(), unit(), unit() + 2.0).normalized();
  m.w_rad_s = 6.0 * Eigen::Vector3d(unit(), unit(), unit());  // up to ~10 rad/s
  m.p0_m = Eigen::Vector3d(unit(), unit(), unit());
  m.v_m_s = 2.0 * Eigen::Vector3d(unit(), unit(), unit());
  const bool gyro = *rc::gen::arbitrary<bool>();
  ConstantVelocityPredictor cv;
  PoseHistory history;
  for (int i = 0; i < 30; ++i) {
    const double t_s = i * 2e-3;
    auto s =
        sample(rotate_at(m.q0, m.w_rad_s, t_s), m.p0_m + m.v_m_s * t_s, 5'000'000 + i * 2'000'000);
    s.has_angular_velocity = gyro;
    s.angular_velocity_rad_s = m.w_rad_s;
    RC_ASSERT(history.add(s, &cv));
  }
  const double h_s = 0.001 * *rc::gen::inRange(0, 101);
  const double t_s = 29 * 2e-3 + h_s;
  const core::Pose got =
      cv.predict(5'000'000 + 29 * 2'000'000 + static_cast<int64_t>(std::llround(h_s * 1e9)));
  RC_ASSERT(angle_deg(got.R, rotate_at(m.q0, m.w_rad_s, t_s).toRotationMatrix()) < 1e-6);
  RC_ASSERT((got.t - (m.p0_m + m.v_m_s * t_s)).norm() < 1e-9);
}

}  // namespace
}  // namespace hd::station
