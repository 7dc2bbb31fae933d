#include "station/app/score_sweep.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "core/config/config_error.h"
#include "sim/scene/scene_file.h"
#include "station/app/output_file.h"
#include "station/app/report_text.h"
#include "station/app/scene_locator.h"

namespace hd::station {
namespace {

namespace fs = std::filesystem;

// The scene with the condition's camera delay and model period (its model delay kept, or the
// default scene's 0.3 s).
sim::Scene with_condition(sim::Scene scene, const SweepCondition& c) {
  const uint64_t seed = scene.effects.camera_delay ? scene.effects.camera_delay->seed : 3;
  scene.effects.camera_delay = sim::DelayEffect{c.delay_mean_ms, c.delay_jitter_ms, seed};
  sim::ModelStalenessEffect model;
  if (scene.effects.model_staleness)
    model = *scene.effects.model_staleness;
  else
    model.delay_s = 0.3;
  model.period_s = c.model_period_s;
  scene.effects.model_staleness = model;
  return scene;
}

// The scenes of the sweep: the one given, or every file of scenes/ that reads as a scene (the
// station configs beside them do not).
std::vector<std::string> sweep_scenes(const std::string& given) {
  if (!given.empty()) return {given};
  const std::string default_scene = scene_or_default("", "hybrid-station score --sweep", "");
  const fs::path dir = fs::path(default_scene).parent_path();
  std::vector<std::string> scenes;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".yaml") scenes.push_back(e.path().string());
  // The default scene first, the others by name.
  std::sort(scenes.begin(), scenes.end(), [&](const std::string& a, const std::string& b) {
    const bool da = fs::path(a) == fs::path(default_scene),
               db = fs::path(b) == fs::path(default_scene);
    return da != db ? da : a < b;
  });
  std::vector<std::string> readable;
  for (const std::string& s : scenes) {
    try {
      sim::load_scene(s);
      readable.push_back(s);
    } catch (const config::ConfigError&) {
      std::printf("  (skipped %s: not a scene file)\n", s.c_str());
    }
  }
  return readable;
}

std::string cell(double v, const char* f) {
  return std::isfinite(v) ? fmt(f, v) : std::string("-");
}

}  // namespace

std::vector<SweepCondition> default_sweep_conditions() {
  return {{"delay 20+-10 ms / model 1 s", 20, 10, 1.0},
          {"delay 20+-10 ms / model 4 s", 20, 10, 4.0},
          {"delay 50+-20 ms / model 1 s", 50, 20, 1.0},
          {"delay 50+-20 ms / model 4 s", 50, 20, 4.0}};
}

std::vector<SweepMethod> default_sweep_methods() {
  return {{"video only", "abrupt", 1e9, "kalman"},
          {"synthetic only", "abrupt", 0.0, "kalman"},
          {"abrupt", "abrupt", NAN, "kalman"},
          {"global blend", "global_blend", NAN, "kalman"},
          {"per-pixel blend", "per_pixel", NAN, "kalman"},
          {"per-pixel / no predictor", "per_pixel", NAN, "none"},
          {"per-pixel / constant velocity", "per_pixel", NAN, "cv"}};
}

int run_score_sweep(const ScoreOptions& options) {
  const std::string out = options.station.out_dir;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (!fs::is_directory(out, ec))
    throw std::runtime_error("--out " + out + ": cannot create the directory");
  const std::vector<std::string> scenes = sweep_scenes(options.station.scene_path);
  const std::vector<SweepCondition> conditions = default_sweep_conditions();
  const std::vector<SweepMethod> methods = default_sweep_methods();
  // 30 Hz unless told: a frame costs the same at any rate, and the transitions' lag is in seconds.
  const double rate_hz = options.station.rate_hz > 0.0 ? options.station.rate_hz : 30.0;
  const std::size_t runs = scenes.size() * conditions.size() * methods.size();
  std::printf(
      "score --sweep: %zu scenes x %zu conditions x %zu methods = %zu runs at %g Hz, "
      "both eyes unless --mono; each run's outputs under %s/<scene>/<condition>/<method>/\n",
      scenes.size(), conditions.size(), methods.size(), runs, rate_hz, out.c_str());

  std::string csv =
      "scene,condition,method,psnr_mean_db,psnr_p5_db,ssim_mean,ssim_p5,video_or_hybrid_share,"
      "tick_ms_per_frame,x_real_time\n";
  std::string md =
      "| scene | condition | method | PSNR mean (dB) | PSNR p5 (dB) | SSIM mean | SSIM p5 | "
      "video or hybrid | CPU ms/frame |\n|---|---|---|---|---|---|---|---|---|\n";
  std::printf("  %-12s %-28s %-30s %8s %8s %7s %7s %7s %8s\n", "scene", "condition", "method",
              "PSNR", "p5", "SSIM", "p5", "shown", "ms/frame");
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t done = 0;
  for (const std::string& scene_path : scenes) {
    const sim::Scene scene = sim::load_scene(scene_path);
    const std::string scene_name = fs::path(scene_path).stem().string();
    for (std::size_t c = 0; c < conditions.size(); ++c) {
      for (std::size_t m = 0; m < methods.size(); ++m) {
        const SweepCondition& cond = conditions[c];
        const SweepMethod& method = methods[m];
        ScoreOptions run = options;
        run.sweep = false;
        run.quiet = true;
        run.save_frames = 0;
        run.error_maps = false;
        run.station.rate_hz = rate_hz;
        run.station.transition_mode = method.transition;
        run.station.predictor = method.predictor;
        if (std::isfinite(method.m_t)) run.station.m_t = method.m_t;
        run.station.out_dir =
            out + "/" + scene_name + "/c" + std::to_string(c) + "/m" + std::to_string(m);
        const ScoreFigures f = score_scene(with_condition(scene, cond), scene_path, run);
        ++done;
        std::printf("  %-12s %-28s %-30s %8s %8s %7s %7s %6.0f%% %8.2f   (%zu/%zu)\n",
                    scene_name.c_str(), cond.name.c_str(), method.name.c_str(),
                    cell(f.psnr_mean_db, "%.2f").c_str(), cell(f.psnr_p5_db, "%.2f").c_str(),
                    cell(f.ssim_mean, "%.4f").c_str(), cell(f.ssim_p5, "%.4f").c_str(),
                    100.0 * f.video_share, f.tick_ms, done, runs);
        std::fflush(stdout);
        csv += scene_name + "," + cond.name + "," + method.name + "," +
               cell(f.psnr_mean_db, "%.3f") + "," + cell(f.psnr_p5_db, "%.3f") + "," +
               cell(f.ssim_mean, "%.5f") + "," + cell(f.ssim_p5, "%.5f") + "," +
               fmt("%.4f", f.video_share) + "," + fmt("%.3f", f.tick_ms) + "," +
               fmt("%.3f", f.x_real_time) + "\n";
        md += "| " + scene_name + " | " + cond.name + " | " + method.name + " | " +
              cell(f.psnr_mean_db, "%.2f") + " | " + cell(f.psnr_p5_db, "%.2f") + " | " +
              cell(f.ssim_mean, "%.3f") + " | " + cell(f.ssim_p5, "%.3f") + " | " +
              fmt("%.0f %%", 100.0 * f.video_share) + " | " + fmt("%.2f", f.tick_ms) + " |\n";
        // Written after every run, so an interrupted sweep keeps what it measured.
        write_text_atomically(csv, out + "/sweep.csv");
        write_text_atomically(md, out + "/sweep.md");
      }
    }
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  %zu runs in %.0f s; wrote %s/sweep.csv and %s/sweep.md\n", runs, wall_s,
              out.c_str(), out.c_str());
  return 0;
}

}  // namespace hd::station
