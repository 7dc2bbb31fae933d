// hybrid-bench-prediction: prediction error against horizon for no prediction, constant velocity
// and the Kalman filter, on simulated seated head motion with tracker noise. Also the cost per
// sample + prediction of each, measured in the same run.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "station/prediction/constant_velocity_predictor.h"
#include "station/prediction/kalman_predictor.h"
#include "station/prediction/pose_history.h"
#include "station/prediction/simulated_head_motion.h"

namespace {

using namespace hd::station;

struct Errors {
  std::vector<double> deg, mm;
};

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}
double p95(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(v.size()))) - 1];
}

void run_table(double rate_hz, bool gyro, double seconds) {
  const SimulatedHeadMotion motion;
  const TrackerNoise noise;
  KalmanParams kp;
  kp.orientation_noise_rad = noise.orientation_rad;
  kp.gyro_noise_rad_s = noise.gyro_rad_s;
  kp.position_noise_m = noise.position_m;
  std::unique_ptr<PosePredictor> preds[3] = {std::make_unique<HoldPredictor>(),
                                             std::make_unique<ConstantVelocityPredictor>(),
                                             std::make_unique<KalmanPredictor>(kp)};
  constexpr int kHorizons = 11;
  Errors err[3][kHorizons];
  double cost_ns[3] = {0, 0, 0};
  const int64_t period_ns = static_cast<int64_t>(std::llround(1e9 / rate_hz));
  const int n = static_cast<int>(seconds * rate_hz);
  SimulatedTracker tracker(motion, noise, gyro, 11);
  PoseHistory history[3];
  for (int i = 0; i < n; ++i) {
    const int64_t t = 1'000'000'000 + i * period_ns;
    const hd::drivers::PoseSample s = tracker.sample(t);
    const bool evaluate = i * period_ns > 1'000'000'000 && i % 5 == 0;  // after 1 s warm-up
    for (int p = 0; p < 3; ++p) {
      const auto c0 = std::chrono::steady_clock::now();
      history[p].add(s, preds[p].get());
      hd::core::Pose predicted = preds[p]->predict(t + 20'000'000);
      const auto c1 = std::chrono::steady_clock::now();
      cost_ns[p] += static_cast<double>(
          std::chrono::duration_cast<std::chrono::nanoseconds>(c1 - c0).count());
      if (!evaluate) continue;
      for (int h = 0; h < kHorizons; ++h) {
        const int64_t target = t + int64_t{h} * 10'000'000;
        predicted = preds[p]->predict(target);
        const hd::core::Pose truth = motion.pose(static_cast<double>(target) * 1e-9);
        err[p][h].deg.push_back(Eigen::AngleAxisd(truth.R.transpose() * predicted.R).angle() *
                                180.0 / M_PI);
        err[p][h].mm.push_back((truth.t - predicted.t).norm() * 1e3);
      }
    }
  }
  std::printf(
      "\n%.0f Hz tracker%s, noise %.2f deg / %.1f mm%s, %.0f s of motion, %zu predictions per "
      "cell\n",
      rate_hz, gyro ? " with gyro" : " without gyro", noise.orientation_rad * 180.0 / M_PI,
      noise.position_m * 1e3, gyro ? "" : " (omega differenced)", seconds, err[0][0].deg.size());
  std::printf(
      "horizon |        none: deg mean/p95   mm mean/p95 | const. velocity: deg mean/p95   mm "
      "mean/p95 |"
      "          Kalman: deg mean/p95   mm mean/p95\n");
  for (int h = 0; h < kHorizons; ++h) {
    std::printf("%4d ms ", h * 10);
    for (int p = 0; p < 3; ++p)
      std::printf("| %12.3f %6.3f %9.2f %6.2f ", mean(err[p][h].deg), p95(err[p][h].deg),
                  mean(err[p][h].mm), p95(err[p][h].mm));
    std::printf("\n");
  }
  std::printf(
      "cost per sample + one prediction: none %.0f ns, constant velocity %.0f ns, Kalman %.0f ns\n",
      cost_ns[0] / n, cost_ns[1] / n, cost_ns[2] / n);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-prediction: error of the predicted head pose (none, constant velocity, "
      "Kalman) against the true pose at sample time + horizon, and the cost of each"};
  double seconds = 60.0;
  app.add_option("--seconds", seconds, "simulated head motion per table (at least 2 s)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  seconds = std::max(2.0, seconds);
  std::printf(
      "hybrid-bench-prediction: orientation (deg) and position (mm) error of the predicted head "
      "pose\n"
      "against the true pose at sample time + horizon. Motion: yaw +-38 deg, pitch +-14, roll "
      "+-3,\n"
      "position +-6 cm, sums of sinusoids 0.2-1.9 Hz "
      "(station/prediction/simulated_head_motion.cpp).\n");
  run_table(1000.0, true, seconds);
  run_table(500.0, false, seconds);
  return 0;
}
