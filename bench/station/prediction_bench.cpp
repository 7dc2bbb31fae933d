// hybrid-bench-prediction: prediction error against horizon for no prediction, constant velocity
// and the Kalman filter, on simulated seated head motion with tracker noise. The Kalman filter's
// default process noise was chosen on one motion (HeadMotionProfile::kTuning), so every table is
// printed twice: on that motion, and on a held-out motion with other frequencies, phases and
// amplitudes and another noise seed, which nothing was tuned on. A grid of process noises then
// shows which one each motion would pick, beside the default. Also the cost per sample +
// prediction of each predictor, measured in the same run.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
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

struct Tracker {
  double rate_hz;
  bool gyro;
};

struct Motion {
  const char* name;
  HeadMotionProfile profile;
  uint32_t noise_seed;
};
constexpr Motion kTuningMotion{"tuning motion (the Kalman defaults were chosen on it)",
                               HeadMotionProfile::kTuning, 11};
constexpr Motion kHeldOutMotion{"held-out motion (not tuned on)", HeadMotionProfile::kHeldOut, 23};

// The filter as the station runs it: its measurement noise is the tracker's, its process noise
// the defaults unless given.
KalmanParams kalman_params(const TrackerNoise& noise, double angular_psd, double linear_psd) {
  KalmanParams kp;
  kp.orientation_noise_rad = noise.orientation_rad;
  kp.gyro_noise_rad_s = noise.gyro_rad_s;
  kp.position_noise_m = noise.position_m;
  kp.angular_accel_psd = angular_psd;
  kp.linear_accel_psd = linear_psd;
  return kp;
}

// Feeds `preds` the tracker's samples for `seconds` (after 1 s of warm-up, every 5th sample is
// scored) and collects each predictor's error at each horizon h * 10 ms, h < errs[p].size().
void run(const Motion& m, const Tracker& tr, double seconds, std::vector<PosePredictor*> preds,
         std::vector<std::vector<Errors>>& errs, std::vector<double>* cost_ns) {
  const SimulatedHeadMotion motion(1.0, {0.0, 0.0, 0.0}, m.profile);
  const TrackerNoise noise;
  SimulatedTracker tracker(motion, noise, tr.gyro, m.noise_seed);
  const int64_t period_ns = static_cast<int64_t>(std::llround(1e9 / tr.rate_hz));
  const int n = static_cast<int>(seconds * tr.rate_hz);
  std::vector<PoseHistory> history(preds.size());
  if (cost_ns) cost_ns->assign(preds.size(), 0.0);
  for (int i = 0; i < n; ++i) {
    const int64_t t = 1'000'000'000 + i * period_ns;
    const hd::drivers::PoseSample s = tracker.sample(t);
    const bool evaluate = i * period_ns > 1'000'000'000 && i % 5 == 0;  // after 1 s warm-up
    for (std::size_t p = 0; p < preds.size(); ++p) {
      const auto c0 = std::chrono::steady_clock::now();
      history[p].add(s, preds[p]);
      hd::core::Pose predicted = preds[p]->predict(t + 20'000'000);
      const auto c1 = std::chrono::steady_clock::now();
      if (cost_ns)
        (*cost_ns)[p] += static_cast<double>(
            std::chrono::duration_cast<std::chrono::nanoseconds>(c1 - c0).count());
      if (!evaluate) continue;
      for (std::size_t h = 0; h < errs[p].size(); ++h) {
        const int64_t target = t + static_cast<int64_t>(h) * 10'000'000;
        predicted = preds[p]->predict(target);
        const hd::core::Pose truth = motion.pose(static_cast<double>(target) * 1e-9);
        errs[p][h].deg.push_back(Eigen::AngleAxisd(truth.R.transpose() * predicted.R).angle() *
                                 180.0 / M_PI);
        errs[p][h].mm.push_back((truth.t - predicted.t).norm() * 1e3);
      }
    }
  }
  if (cost_ns)
    for (double& c : *cost_ns) c /= n;
}

// Mean error 50 ms ahead of none, constant velocity and Kalman: {deg, mm} each.
using At50 = std::array<std::array<double, 2>, 3>;

At50 print_table(const Motion& m, const Tracker& tr, double seconds) {
  const TrackerNoise noise;
  const KalmanParams defaults;
  HoldPredictor hold;
  ConstantVelocityPredictor cv;
  KalmanPredictor kf(kalman_params(noise, defaults.angular_accel_psd, defaults.linear_accel_psd));
  constexpr int kHorizons = 11;
  std::vector<std::vector<Errors>> err(3, std::vector<Errors>(kHorizons));
  std::vector<double> cost_ns;
  run(m, tr, seconds, {&hold, &cv, &kf}, err, &cost_ns);
  std::printf("\n%.0f Hz tracker%s, %s, %.0f s, %zu predictions per cell\n", tr.rate_hz,
              tr.gyro ? " with gyro" : " without gyro (omega differenced)", m.name, seconds,
              err[0][0].deg.size());
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
      cost_ns[0], cost_ns[1], cost_ns[2]);
  At50 out{};
  for (int p = 0; p < 3; ++p) out[p] = {mean(err[p][5].deg), mean(err[p][5].mm)};
  return out;
}

// The Kalman filter over a grid of process noises (angular psd i with linear psd i: the
// orientation and position filters are independent, so one run scores both), scored by the mean
// error 50 ms ahead; prints the best of each beside the defaults.
void print_tuning(const Motion& m, const Tracker& tr, double seconds) {
  constexpr std::array<double, 9> kAngular = {0.25, 0.5, 1, 2, 4, 8, 16, 32, 64};
  constexpr std::array<double, 9> kLinear = {0.025, 0.05, 0.1, 0.2, 0.4, 0.8, 1.6, 3.2, 6.4};
  const TrackerNoise noise;
  const KalmanParams defaults;
  std::vector<std::unique_ptr<KalmanPredictor>> filters;
  std::vector<PosePredictor*> preds;
  for (std::size_t i = 0; i < kAngular.size(); ++i) {
    filters.push_back(
        std::make_unique<KalmanPredictor>(kalman_params(noise, kAngular[i], kLinear[i])));
    preds.push_back(filters.back().get());
  }
  filters.push_back(std::make_unique<KalmanPredictor>(
      kalman_params(noise, defaults.angular_accel_psd, defaults.linear_accel_psd)));
  preds.push_back(filters.back().get());
  std::vector<std::vector<Errors>> err(preds.size(), std::vector<Errors>(6));
  run(m, tr, seconds, preds, err, nullptr);
  std::size_t best_a = 0, best_l = 0;
  for (std::size_t i = 0; i < kAngular.size(); ++i) {
    if (mean(err[i][5].deg) < mean(err[best_a][5].deg)) best_a = i;
    if (mean(err[i][5].mm) < mean(err[best_l][5].mm)) best_l = i;
  }
  const std::size_t d = kAngular.size();
  std::printf(
      "%5.0f Hz%s | %-8s | %7.2f -> %.3f deg  default %.2f -> %.3f deg | %6.3f -> %.2f mm  "
      "default %.2f -> %.2f mm\n",
      tr.rate_hz, tr.gyro ? " gyro   " : " no gyro",
      m.profile == HeadMotionProfile::kTuning ? "tuning" : "held-out", kAngular[best_a],
      mean(err[best_a][5].deg), defaults.angular_accel_psd, mean(err[d][5].deg), kLinear[best_l],
      mean(err[best_l][5].mm), defaults.linear_accel_psd, mean(err[d][5].mm));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-prediction: error of the predicted head pose (none, constant velocity, "
      "Kalman) against the true pose at sample time + horizon, on the motion the Kalman filter "
      "was tuned on and on a held-out one, and the cost of each"};
  double seconds = 60.0;
  app.add_option("--seconds", seconds, "simulated head motion per table (at least 2 s)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  seconds = std::max(2.0, seconds);
  std::printf(
      "hybrid-bench-prediction: orientation (deg) and position (mm) error of the predicted head "
      "pose\n"
      "against the true pose at sample time + horizon; tracker noise 0.10 deg / 0.3 mm / gyro "
      "0.01 rad/s.\n"
      "Tuning motion: yaw +-38 deg, pitch +-14, roll +-3, position +-6 cm, sums of sinusoids "
      "0.2-1.9 Hz,\n"
      "noise seed 11. Held-out motion: yaw +-37 deg, pitch +-15, roll +-5, position +-5.5 cm, other "
      "sums of\n"
      "sinusoids 0.18-2.6 Hz, noise seed 23 (station/prediction/simulated_head_motion.cpp).\n"
      "The Kalman rows use the station's default process noise (KalmanParams: %.1f "
      "rad/s^2/sqrt(Hz), "
      "%.1f m/s^2/sqrt(Hz)).\n",
      KalmanParams{}.angular_accel_psd, KalmanParams{}.linear_accel_psd);
  const Tracker trackers[] = {{1000.0, true}, {500.0, false}};
  At50 at50[2][2];
  for (int t = 0; t < 2; ++t) {
    at50[t][0] = print_table(kTuningMotion, trackers[t], seconds);
    at50[t][1] = print_table(kHeldOutMotion, trackers[t], seconds);
  }
  std::printf(
      "\nMean error 50 ms ahead, deg / mm (the station predicts about 50 ms):\n"
      "tracker          | motion   |          none |   const. vel. |        Kalman\n");
  for (int t = 0; t < 2; ++t)
    for (int m = 0; m < 2; ++m) {
      std::printf("%5.0f Hz%s | %-8s ", trackers[t].rate_hz,
                  trackers[t].gyro ? " gyro   " : " no gyro", m == 0 ? "tuning" : "held-out");
      for (int p = 0; p < 3; ++p)
        std::printf("| %5.3f / %5.2f ", at50[t][m][p][0], at50[t][m][p][1]);
      std::printf("\n");
    }
  std::printf(
      "\nKalman process noise each motion would pick (grid 0.25..64 rad/s^2/sqrt(Hz), "
      "0.025..6.4 m/s^2/sqrt(Hz),\nfactors of 2), by mean error 50 ms ahead, beside the "
      "defaults:\n"
      "tracker          | motion   | best angular psd -> error, default -> error | best linear psd "
      "-> error, default -> error\n");
  for (const Tracker& tr : trackers) {
    print_tuning(kTuningMotion, tr, seconds);
    print_tuning(kHeldOutMotion, tr, seconds);
  }
  return 0;
}
