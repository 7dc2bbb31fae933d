#pragma once
// `hybrid-station score`: the station's own frame path (StationFrame's tick, the CPU compositor,
// the camera pipelines, the head's alignment and predictor, the model updater) run on the scene's
// clock, and every displayed frame scored against the truth the simulator knows.
//
// Time: render of frame k starts at scene t = k / rate, its display time is one frame period and
// the scan-out later. Before each frame the scene's stepped devices deliver what they would have
// by then (sim/stepped_camera.h, sim/stepped_head.h), the pipelines and the head's alignment take
// it, and the model updater takes frames every refresh period and publishes them the scene's
// model delay later. Rendering cost never moves this clock: it is measured on CLOCK_MONOTONIC and
// reported beside the scores, with the run's speed as a multiple of real time. So the same scene
// and seed give the same score.csv on any machine under any load.
//
// Truth: per frame and eye, the scene as it is at the display time (moving objects placed then,
// no camera effects) rendered by the CPU compositor from the true eye pose (the head's motion
// without tracker effects), at the eye's size. The station runs with marking and guidance off
// and no HUD, so the picture scored is the picture without the operator's cues; with an HMD
// profile it is scored before the lens pass.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "sim/scene/scene.h"
#include "station/app/run_options.h"

namespace hd::station {

struct ScoreOptions {
  bool sweep = false;  ///< the system-level table instead of one run (station/app/score_sweep.h)
  bool quiet = false;  ///< no start report, progress, plots or contact sheet: one run of a sweep
  RunOptions station;  ///< scene, out, frames / seconds, rate, mono, hmd, m_t, eps, ...
  uint64_t save_frames = 0;  ///< every Nth frame's shown and truth PNGs (0: none)
  /// Per-pixel error maps of the same frames (of every 90th without save_frames).
  bool error_maps = false;
  /// Content older than this at its display time counts in old_fraction (score.csv).
  double age_bound_ms = 100.0;
};

/// A run's headline figures (the rest is in its score.json).
struct ScoreFigures {
  double psnr_mean_db = NAN, psnr_p5_db = NAN, ssim_mean = NAN, ssim_p5 = NAN;
  double video_share = 0.0;  ///< share of eye-frames shown as video or hybrid
  double tick_ms = 0.0;      ///< the station's tick, CPU ms per frame on this machine
  double x_real_time = 0.0;
  std::size_t eye_frames = 0;
};

/// One scored run of `scene` (read from scene_path) into options.station.out_dir. Throws
/// config::ConfigError for a bad scene, std::runtime_error when the station cannot start or an
/// output cannot be written.
ScoreFigures score_scene(sim::Scene scene, const std::string& scene_path,
                         const ScoreOptions& options);

/// Runs (or sweeps) and writes DIR/score.csv and DIR/score.json; returns the program's exit code
/// (0 done, 1 runtime failure, 2 a bad scene file, 3 the station cannot start).
int run_score(const ScoreOptions& options);

}  // namespace hd::station
