#pragma once
// `hybrid-station score --sweep`: accuracy against time for the whole system. Each scene is
// scored under two camera delays and two model periods, with every method (video only,
// synthetic only, the three transition modes, and the per-pixel blend with each predictor), and
// one table collects PSNR and SSIM (mean, p5), the share shown as video or hybrid, and the
// station's CPU ms per frame.
//
// Every cell is a real `score` run of the station (not a replay), so SSIM is measured too. A
// condition replaces the scene's camera_delay and model_staleness effects (the model's
// publishing delay is kept, 0.3 s where the scene has none); every other effect stays as the
// scene lists it. "Video only" is the abrupt mode with m_t = 1e9 px (video whenever a camera is
// usable), "synthetic only" the abrupt mode with m_t = 0.

#include <string>
#include <vector>

#include "station/app/score_run.h"

namespace hd::station {

struct SweepCondition {
  std::string name;
  double delay_mean_ms = 0.0, delay_jitter_ms = 0.0;  ///< camera_delay
  double model_period_s = 1.0;                        ///< model_staleness period
};

struct SweepMethod {
  std::string name;
  std::string transition;  ///< abrupt | global_blend | per_pixel
  double m_t = NAN;        ///< NaN: the scene's (or the station config's)
  std::string predictor;   ///< none | cv | kalman
};

/// The grid: 20 +- 10 ms and 50 +- 20 ms camera delay, model periods 1 s and 4 s.
std::vector<SweepCondition> default_sweep_conditions();
/// Video only, synthetic only, abrupt, global blend and per-pixel blend (Kalman predictor), and
/// the per-pixel blend with no predictor and with constant velocity.
std::vector<SweepMethod> default_sweep_methods();

/// The scenes (options.station.scene_path, or every scene of the source tree's scenes/ when it
/// is empty), each condition and method; writes DIR/sweep.csv, DIR/sweep.md and each run's
/// outputs under DIR/<scene>/<condition>/<method>/. Returns the exit code like run_score.
int run_score_sweep(const ScoreOptions& options);

}  // namespace hd::station
