// `hybrid-station score`: the command line. The work is in score_run.cpp.
#include <memory>

#include "station/app/command.h"
#include "station/app/score_run.h"
#include "station/app/station_config.h"

namespace hd::station {
namespace {

const CommandRegistrar kRegister{[](CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<ScoreOptions>();
  RunOptions& o = opts->station;
  o.out_dir = "out/score";
  CLI::App* cmd = app.add_subcommand(
      "score",
      "Run the station on a scene's clock and score every frame against the truth the simulator "
      "knows (PSNR, SSIM, GMSD per frame and eye; split by what each pixel showed).\n"
      "The same scene gives the same scores on any machine under any load.\n"
      "Examples:\n"
      "  hybrid-station score --out out/score\n"
      "  hybrid-station score --scene scenes/default.yaml --transition abrupt --save-frames 90 "
      "--out out/score-abrupt\n"
      "Writes DIR/score.csv (one row per frame and eye), DIR/score.json (means and "
      "percentiles, overall and by variant, the settings, m against the truth, the best m_t "
      "and eps per transition mode, and the run's speed), DIR/tuning.csv (every m_t and eps "
      "replayed over the run), the plots score_trace.png and m_scatter.png, and score_sheet.png "
      "(shown | truth | error of six frames).\n"
      "Exit codes: 0 done, 1 runtime failure, 2 bad scene file (file:line:col: field), 3 the "
      "station cannot start.");
  cmd->add_option("--scene", o.scene_path,
                  "Scene file (default: scenes/default.yaml, from the current directory or the "
                  "source tree)");
  cmd->add_option("--out", o.out_dir, "Output directory (created)")->capture_default_str();
  auto* frames = cmd->add_option("--frames", o.frames, "Frames to score")
                     ->check(CLI::Range(uint64_t{1}, uint64_t{100'000'000}));
  cmd->add_option("--seconds", o.seconds, "Seconds of the scene to score (default: its duration)")
      ->check(CLI::Range(0.01, 1e6))
      ->excludes(frames);
  cmd->add_option("--rate", o.rate_hz, "Display rate in Hz (default 90)")
      ->check(CLI::Range(1.0, 1000.0));
  cmd->add_flag("--mono", o.mono, "One eye (a monitor) instead of a stereo HMD");
  add_video_view_option(*cmd, o);
  cmd->add_option("--hmd", o.hmd,
                  "HMD profile (name or .yaml): its eyes, scored before the lens pass");
  cmd->add_option("--predictor", o.predictor, "none | cv | kalman")
      ->check(CLI::IsMember({"none", "cv", "kalman"}));
  cmd->add_option("--m-t", o.m_t, "Transition threshold m_t (px)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--eps", o.eps, "Transition half band eps (px)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--transition", o.transition_mode, "abrupt | global_blend | per_pixel")
      ->check(CLI::IsMember(transition_mode_names()));
  // Rendering cost never moves the scene's clock, so the run may use every core it has.
  o.threads = 2;
  cmd->add_option("--threads", o.threads, "CPU compositor threads (the scores do not depend on it)")
      ->check(CLI::Range(1, 8))
      ->capture_default_str();
  cmd->add_option("--save-frames", opts->save_frames,
                  "Every Nth frame: DIR/frames/NNNNNN_eyeE_shown.png and _truth.png");
  cmd->add_option("--age-bound-ms", opts->age_bound_ms,
                  "Content older than this at its display time counts in old_fraction")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_flag("--sweep", opts->sweep,
                "Accuracy against time: every scene of scenes/ (or --scene) under camera delays "
                "20+-10 and 50+-20 ms and model periods 1 and 4 s, with every method and "
                "predictor, at 30 Hz unless --rate; writes DIR/sweep.csv and DIR/sweep.md");
  cmd->add_flag("--error-maps", opts->error_maps,
                "Per-pixel error maps DIR/frames/NNNNNN_eyeE_error.png of the same frames (every "
                "90th without --save-frames): the largest channel error, 0..64 DN, INFERNO");
  cmd->callback([opts, &exit_code] { exit_code = run_score(*opts); });
}};

}  // namespace
}  // namespace hd::station
