// Kalman predictor: converges on noisy constant motion to the accuracy the noise allows (checked
// against an ordinary least-squares line fit, the optimal estimator for that case), is exact on
// noise-free constant rotation, and beats no prediction on simulated head motion.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "station/prediction/constant_velocity_predictor.h"
#include "station/prediction/kalman_predictor.h"
#include "station/prediction/pose_history.h"
#include "station/prediction/simulated_head_motion.h"

namespace hd::station {
namespace {

// Three draws in a fixed order, z first as GCC drew the unsequenced arguments of
// Eigen::Vector3d(n(rng), n(rng), n(rng)) when the bounds below were set (clang draws x first).
Eigen::Vector3d gauss3(std::normal_distribution<double>& n, std::mt19937_64& rng) {
  const double z = n(rng), y = n(rng), x = n(rng);
  return {x, y, z};
}

constexpr int kSamples = 500;
constexpr int64_t kPeriodNs = 1'000'000;

// Sum over samples of (t - mean t)^2, the OLS slope's information.
double sxx(int n, double dt) {
  double mean = (n - 1) * dt / 2.0, s = 0.0;
  for (int i = 0; i < n; ++i) s += (i * dt - mean) * (i * dt - mean);
  return s;
}

TEST(PredictionKalman, NoisyConstantVelocityMatchesLeastSquaresAccuracy) {
  const double sigma = 0.0005;
  KalmanParams kp;
  kp.position_noise_m = sigma;
  kp.linear_accel_psd = 1e-6;  // truly constant velocity
  const Eigen::Vector3d v_true(0.3, -0.1, 0.05), p0(0.2, 1.0, -0.4);
  std::mt19937_64 rng(42);
  std::normal_distribution<double> n01(0.0, 1.0);
  double sq_err_v = 0.0, sq_err_p = 0.0, max_gap_ols_v = 0.0;
  int count = 0;
  const double dt = kPeriodNs * 1e-9;
  const double theory_sd_v = sigma / std::sqrt(sxx(kSamples, dt));
  for (int trial = 0; trial < 100; ++trial) {
    KalmanPredictor kf(kp);
    PoseHistory h;
    // OLS on x alone, the independent second method.
    double st = 0, sx = 0, stt = 0, stx = 0;
    for (int i = 0; i < kSamples; ++i) {
      const double t = i * dt;
      drivers::PoseSample s;
      s.T_tracker_head.t = p0 + v_true * t + sigma * gauss3(n01, rng);
      s.has_position = true;
      s.host_timestamp_ns = 1'000'000 + i * kPeriodNs;
      ASSERT_TRUE(h.add(s, &kf));
      st += t, sx += s.T_tracker_head.t.x(), stt += t * t, stx += t * s.T_tracker_head.t.x();
    }
    const double slope = (kSamples * stx - st * sx) / (kSamples * stt - st * st);
    max_gap_ols_v = std::max(max_gap_ols_v, std::abs(kf.velocity_m_s().x() - slope));
    for (int a = 0; a < 3; ++a) {
      sq_err_v += std::pow(kf.velocity_m_s()(a) - v_true(a), 2);
      const double t_last = (kSamples - 1) * dt;
      sq_err_p += std::pow(kf.position_m()(a) - (p0(a) + v_true(a) * t_last), 2);
      ++count;
    }
    if (trial == 0) {
      // The filter's own variance equals the OLS slope variance sigma^2 / Sxx.
      EXPECT_NEAR(std::sqrt(kf.position_covariance_per_axis()(1, 1)), theory_sd_v,
                  0.05 * theory_sd_v);
    }
  }
  const double rms_v = std::sqrt(sq_err_v / count);
  const double rms_p = std::sqrt(sq_err_p / count);
  // OLS end-point sd: sigma * sqrt(1/N + (t_N - mean t)^2 / Sxx) = ~2 sigma / sqrt(N).
  const double t_last = (kSamples - 1) * dt, mean_t = t_last / 2.0;
  const double theory_sd_p =
      sigma * std::sqrt(1.0 / kSamples + (t_last - mean_t) * (t_last - mean_t) / sxx(kSamples, dt));
  EXPECT_GT(rms_v, 0.8 * theory_sd_v);
  EXPECT_LT(rms_v, 1.2 * theory_sd_v);
  EXPECT_GT(rms_p, 0.8 * theory_sd_p);
  EXPECT_LT(rms_p, 1.2 * theory_sd_p);
  EXPECT_LT(max_gap_ols_v, 0.02 * theory_sd_v);
}

TEST(PredictionKalman, NoisyConstantRotationRateConvergesToTheoreticalAccuracy) {
  const double sigma = 0.002;
  KalmanParams kp;
  kp.orientation_noise_rad = sigma;
  kp.angular_accel_psd = 1e-6;
  const Eigen::Vector3d w_true(0.4, 1.0, -0.3);
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0, 1, 1).normalized()));
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double dt = kPeriodNs * 1e-9;
  const double theory_sd_w = sigma / std::sqrt(sxx(kSamples, dt));
  double sq = 0.0;
  int count = 0;
  for (int trial = 0; trial < 60; ++trial) {
    KalmanPredictor kf(kp);
    PoseHistory h;
    for (int i = 0; i < kSamples; ++i) {
      const double t = i * dt;
      const Eigen::Vector3d noise = sigma * gauss3(n01, rng);
      const Eigen::Quaterniond q =
          q0 * Eigen::Quaterniond(Eigen::AngleAxisd(w_true.norm() * t, w_true.normalized())) *
          Eigen::Quaterniond(Eigen::AngleAxisd(noise.norm(), noise.normalized()));
      drivers::PoseSample s;
      s.T_tracker_head = core::Pose::from(q, Eigen::Vector3d::Zero());
      s.host_timestamp_ns = 1'000'000 + i * kPeriodNs;
      ASSERT_TRUE(h.add(s, &kf));
    }
    for (int a = 0; a < 3; ++a, ++count)
      sq += std::pow(kf.angular_velocity_head_rad_s()(a) - w_true(a), 2);
  }
  const double rms = std::sqrt(sq / count);
  EXPECT_GT(rms, 0.75 * theory_sd_w);
  EXPECT_LT(rms, 1.3 * theory_sd_w);
}

TEST(PredictionKalman, NoiseFreeConstantRotationIsPredictedExactly) {
  KalmanParams kp;
  kp.angular_accel_psd = 1e-3;
  KalmanPredictor kf(kp);
  PoseHistory h;
  const Eigen::Vector3d w(0.0, 2.0, 0.5);
  for (int i = 0; i < 400; ++i) {
    drivers::PoseSample s;
    s.T_tracker_head =
        core::Pose::from(Eigen::Quaterniond(Eigen::AngleAxisd(w.norm() * i * 1e-3, w.normalized())),
                         Eigen::Vector3d::Zero());
    s.host_timestamp_ns = (i + 1) * kPeriodNs;
    ASSERT_TRUE(h.add(s, &kf));
  }
  const double t_s = 399e-3 + 0.05;
  const Eigen::Matrix3d truth =
      Eigen::AngleAxisd(w.norm() * t_s, w.normalized()).toRotationMatrix();
  const Eigen::Matrix3d got = kf.predict(400 * kPeriodNs + 50'000'000).R;
  EXPECT_LT(Eigen::AngleAxisd(truth.transpose() * got).angle(), 1e-6);
}

TEST(PredictionKalman, BeatsNoPredictionOnSimulatedHeadMotionAt50ms) {
  SimulatedHeadMotion motion;
  SimulatedTracker tracker(motion, TrackerNoise{}, true);
  KalmanPredictor kf;
  HoldPredictor hold;
  PoseHistory h1, h2;
  double err_kf = 0.0, err_hold = 0.0;
  int n = 0;
  for (int i = 0; i < 6000; ++i) {
    const int64_t t = (i + 1) * kPeriodNs;
    const auto s = tracker.sample(t);
    ASSERT_TRUE(h1.add(s, &kf));
    ASSERT_TRUE(h2.add(s, &hold));
    if (i > 500 && i % 10 == 0) {
      const int64_t target = t + 50'000'000;
      const Eigen::Matrix3d truth = motion.pose(target * 1e-9).R;
      err_kf += Eigen::AngleAxisd(truth.transpose() * kf.predict(target).R).angle();
      err_hold += Eigen::AngleAxisd(truth.transpose() * hold.predict(target).R).angle();
      ++n;
    }
  }
  EXPECT_LT(err_kf / n, 0.5 * err_hold / n);
}

}  // namespace
}  // namespace hd::station
