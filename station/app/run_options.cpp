#include "station/app/run_options.h"

#include "drivers/rtp/rtp_uri.h"
#include "sim/scene_epoch.h"
#include "station/app/station_config.h"

namespace hd::station {

void add_video_view_option(CLI::App& cmd, RunOptions& o) {
  cmd.add_option("--video-view", o.video_view,
                 "plane | fitted-plane | model-depth: how every camera's video is laid into the "
                 "picture (default: each camera's video_view, else plane; docs/video-views.md)")
      ->check(CLI::IsMember({"plane", "fitted-plane", "model-depth"}));
}

void add_run_options(CLI::App& cmd, RunOptions& o) {
  auto* scene = cmd.add_option("--scene", o.scene_path,
                               "Scene file: simulated cameras and head (default: "
                               "scenes/default.yaml, from the current directory or the source "
                               "tree)");
  auto* config =
      cmd.add_option("--config", o.config_path, "station.yaml: real devices (docs/station.md)");
  scene->excludes(config);
  cmd.add_option("--out", o.out_dir, "Output directory (created)")->capture_default_str();
  cmd.add_flag("--headless", o.headless, "No window (CPU compositor unless --gl)");
  cmd.add_flag("--gl", o.gl, "OpenGL compositor (windowed unless --headless)");
  auto* frames = cmd.add_option("--frames", o.frames, "Frames to run")
                     ->check(CLI::Range(uint64_t{1}, uint64_t{100'000'000}));
  auto* seconds = cmd.add_option("--seconds", o.seconds,
                                 "Seconds to run (default: the scene's duration; 10 s for a "
                                 "headless --config run; windowed --config runs until Esc)")
                      ->check(CLI::Range(0.01, 1e6));
  frames->excludes(seconds);
  cmd.add_option("--rate", o.rate_hz, "Frame rate in Hz (default: the config's, else 90)")
      ->check(CLI::Range(1.0, 1000.0));
  cmd.add_option("--rate-policy", o.rate_policy,
                 "hold: run at the fastest of the rate, its half, third or quarter that this "
                 "machine holds, changing with the load, as VR runtimes do (default); fixed: "
                 "always the rate, every miss counted")
      ->check(CLI::IsMember({"hold", "fixed"}));
  cmd.add_flag("--loop", o.loop,
               "Scene runs: the head and moving objects start over every duration_s, for runs "
               "longer than the scene (the soak)")
      ->excludes(config);
  cmd.add_option("--video", o.video_path, "Write every frame to this MJPG .avi")
      ->check([](const std::string& p) {
        return p.size() >= 4 && p.compare(p.size() - 4, 4, ".avi") == 0
                   ? std::string()
                   : std::string("the video must be an .avi file (MJPG)");
      });
  cmd.add_option("--png-every", o.png_every, "Write DIR/frame_NNNNNN.png every N frames");
  cmd.add_option("--contact-tiles", o.contact_tiles, "Tiles on contact_sheet.png")
      ->check(CLI::Range(std::size_t{2}, std::size_t{48}));
  cmd.add_flag("--hud-graph", o.hud_graph,
               "Show the stage-delay graph under the HUD from the start (key G toggles it)");
  add_video_view_option(cmd, o);
  cmd.add_flag("--mono", o.mono, "One eye (a monitor) instead of a stereo HMD");
  cmd.add_option("--hmd", o.hmd,
                 "HMD profile: a shipped name (oculus-dk1, osvr-hdk-1.3, neutral) or a .yaml "
                 "file; the eyes are pre-distorted for its lenses (docs/hmd.md)");
  cmd.add_option("--eye-width", o.eye_width, "Eye image width")->check(CLI::Range(16, 4096));
  cmd.add_option("--eye-height", o.eye_height, "Eye image height")->check(CLI::Range(16, 4096));
  cmd.add_option("--predictor", o.predictor, "none | cv | kalman")
      ->check(CLI::IsMember({"none", "cv", "kalman"}));
  cmd.add_option("--scanout-ms", o.scanout_ms, "Vsync to photons")->check(CLI::Range(0.0, 100.0));
  cmd.add_option("--threads", o.threads, "CPU compositor threads")->check(CLI::Range(1, 8));
  cmd.add_option("--m-t", o.m_t, "Transition threshold m_t (px)")->check(CLI::Range(0.0, 1e6));
  cmd.add_option("--eps", o.eps, "Transition half band eps (px)")->check(CLI::Range(0.0, 1e6));
  cmd.add_option("--transition", o.transition_mode, "abrupt | global_blend | per_pixel")
      ->check(CLI::IsMember(transition_mode_names()));
  cmd.add_option("--marking", o.marking, "none | frame | desaturate | checker")
      ->check(CLI::IsMember(marking_style_names()));
  cmd.add_option("--progress", o.progress_s,
                 "Seconds between progress lines (frames, missed deadlines, variants, memory); 0: "
                 "none")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 86400.0));
  cmd.add_option("--cameras-from", o.cameras_from,
                 "Scene runs: take the scene's cameras from the network, camera i from "
                 "rtp://HOST:(PORT + 2 i), as `hybrid-remote --scene` sends them (head, model and "
                 "reconstruction stay simulated here; scripts/demo.sh)")
      ->excludes(config)
      ->check([](const std::string& v) {
        std::string why;
        return drivers::parse_rtp_uri(v, why) ? std::string() : why;
      });
  cmd.add_option("--scene-epoch", o.scene_epoch,
                 "Scene runs: scene t = 0 as a CLOCK_REALTIME instant, seconds since 1970 (give "
                 "hybrid-remote the same); a scene run then ends at t = the scene's duration")
      ->excludes(config)
      ->check([](const std::string& v) {
        std::string why;
        return sim::parse_scene_epoch(v, why) ? std::string() : why;
      });
  cmd.add_option("--camera-wait", o.camera_wait_s,
                 "With --cameras-from: seconds the run waits for every network camera's first "
                 "frame before its first frame (a camera still silent then is not usable until "
                 "it streams)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  cmd.add_option("--warmup", o.warmup, "Frames before render-thread allocations are counted");
  cmd.add_option("--max-log-rows", o.max_log_rows,
                 "frames.csv keeps the first N frames (storage reserved up front)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}));
}

}  // namespace hd::station
