#pragma once
// Everything `hybrid-station run` is told on its command line.

#include <cstdint>
#include <string>

#include <CLI/CLI.hpp>

namespace hd::station {

struct RunOptions {
  std::string scene_path;   ///< --scene: simulated devices from a scene file
  std::string config_path;  ///< --config: real devices from station.yaml
  std::string out_dir = "out/run";
  bool headless = false;
  bool gl = false;
  uint64_t frames = 0;   ///< 0: run for `seconds`
  double seconds = 0.0;  ///< 0: the scene's duration (--scene) or 10 s (--config, headless)
  double rate_hz = 0.0;  ///< 0: the config's display rate, else 90
  /// hold: the fastest divisor of the rate this machine holds (RateHolder); fixed: the rate.
  std::string rate_policy = "hold";
  bool loop = false;       ///< --loop: the scene's motion starts over every duration_s
  std::string video_path;  ///< "" = no video
  uint64_t png_every = 0;  ///< 0 = no PNG frames
  std::size_t contact_tiles = 12;
  bool mono = false;
  std::string hmd;  ///< an HMD profile (name or file) replacing the config's display.hmd
  int eye_width = 0, eye_height = 0;  ///< 0: config / scene hint / 480x400
  std::string predictor;              ///< "": the config's (kalman)
  double scanout_ms = -1.0;           ///< < 0: the config's (2 ms)
  int threads = 1;                    ///< CPU compositor threads
  double m_t = -1.0, eps = -1.0;      ///< < 0: config / scene hint / 40, 10
  std::string transition_mode;        ///< "": config's (per_pixel)
  std::string marking;                ///< "": config's (frame for scenes)
  uint64_t warmup = 30;
  double progress_s = 10.0;              ///< a progress line every this many seconds; 0 = none
  std::size_t max_log_rows = 1'000'000;  ///< frames.csv keeps the first this many frames
  /// --cameras-from rtp://HOST:PORT (scene runs): the scene's camera i is the network camera
  /// rtp://HOST:(PORT + 2 i), sent by `hybrid-remote --scene` (the two-process demo), instead of
  /// being simulated here; head, model and reconstruction stay as the scene sets them.
  std::string cameras_from;
  std::string scene_epoch;    ///< --scene-epoch: scene t = 0 on CLOCK_REALTIME (sim/scene_epoch.h)
  double camera_wait_s = 10;  ///< --camera-wait: how long the loop waits for network cameras
  bool hud_graph = false;     ///< --hud-graph: the stage graph shown from the start (G toggles)
  std::string video_view;     ///< --video-view: every camera's (core/video_view.h); "": each file's
};

/// Adds the options above to the `run` subcommand.
void add_run_options(CLI::App& cmd, RunOptions& o);
/// --video-view alone (`run` and `score`).
void add_video_view_option(CLI::App& cmd, RunOptions& o);

}  // namespace hd::station
