#include "station/app/score_run.h"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "render/compositor/cpu_compositor.h"
#include "render/latency/latency_recorder.h"
#include "render/loop/stepped_clock.h"
#include "sim/scene/scene_file.h"
#include "station/app/frames_csv.h"
#include "station/app/output_file.h"
#include "station/app/report_text.h"
#include "station/app/scene_locator.h"
#include "station/app/score_plots.h"
#include "station/app/station_config.h"
#include "station/app/station_parts.h"
#include "station/prediction/predictor_by_name.h"
#include "station/score/image_scores.h"
#include "station/score/m_against_truth.h"

namespace hd::station {
namespace {

// One eye of one frame.
struct ScoreRow {
  uint64_t frame = 0;
  double t_s = 0.0;  ///< scene time of its display
  int eye = 0;
  core::Variant variant = core::Variant::kSynthetic;
  std::string camera;  ///< the camera whose video is drawn ("" none)
  double m = NAN, w_video = 0.0;
  ImageScores whole;
  /// PSNR over the pixels that showed video only (weight 1), a blend (0 < weight < 1), the model
  /// only (weight 0); NaN when there were none.
  double psnr_video_db = NAN, psnr_blend_db = NAN, psnr_synthetic_db = NAN;
  double video_fraction = 0.0;  ///< the mean per-pixel video weight
  /// The same frame drawn as pure video (the camera on screen, or the one chosen, at weight 1)
  /// and as pure model; NaN for pure video when no camera was usable.
  double psnr_pure_video_db = NAN, psnr_pure_synthetic_db = NAN;
};

render::ImageRgba8 crop(const render::ImageRgba8& im, const render::Viewport& vp) {
  render::ImageRgba8 out;
  out.allocate(vp.width, vp.height);
  for (int y = 0; y < vp.height; ++y)
    std::copy_n(im.row(vp.y + y) + 4 * vp.x, 4 * vp.width, out.row(y));
  return out;
}

std::string number(double v, const char* f = "%.4f") {
  return std::isfinite(v) ? fmt(f, v) : std::string();
}

void write_csv(const std::vector<ScoreRow>& rows, const std::string& path) {
  std::string s =
      "frame,t_s,eye,variant,camera,m,w_video,psnr_db,ssim,gmsd,psnr_video_db,psnr_blend_db,"
      "psnr_synthetic_db,video_fraction,psnr_pure_video_db,psnr_pure_synthetic_db\n";
  for (const ScoreRow& r : rows)
    s += std::to_string(r.frame) + "," + fmt("%.6f", r.t_s) + "," + std::to_string(r.eye) + "," +
         variant_name(r.variant) + "," + r.camera + "," + number(r.m, "%.3f") + "," +
         fmt("%.4f", r.w_video) + "," + number(r.whole.psnr_db) + "," +
         number(r.whole.ssim, "%.5f") + "," + number(r.whole.gmsd, "%.5f") + "," +
         number(r.psnr_video_db) + "," + number(r.psnr_blend_db) + "," +
         number(r.psnr_synthetic_db) + "," + fmt("%.4f", r.video_fraction) + "," +
         number(r.psnr_pure_video_db) + "," + number(r.psnr_pure_synthetic_db) + "\n";
  write_text_atomically(s, path);
}

// Mean and percentiles of the finite values (p5: the bad frames of a "higher is better" score).
nlohmann::json distribution(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return {{"count", 0}};
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) {
    return v[static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1)))];
  };
  double sum = 0.0;
  for (double x : v) sum += x;
  return {{"count", v.size()},
          {"mean", sum / static_cast<double>(v.size())},
          {"p5", at(0.05)},
          {"p50", at(0.5)},
          {"p95", at(0.95)}};
}

nlohmann::json scores_of(const std::vector<const ScoreRow*>& rows) {
  std::vector<double> psnr, ssim, gmsd, pv, ps, vf;
  for (const ScoreRow* r : rows) {
    psnr.push_back(r->whole.psnr_db);
    ssim.push_back(r->whole.ssim);
    gmsd.push_back(r->whole.gmsd);
    pv.push_back(r->psnr_video_db);
    ps.push_back(r->psnr_synthetic_db);
    vf.push_back(r->video_fraction);
  }
  return {{"eye_frames", rows.size()},         {"psnr_db", distribution(psnr)},
          {"ssim", distribution(ssim)},        {"gmsd", distribution(gmsd)},
          {"psnr_video_db", distribution(pv)}, {"psnr_synthetic_db", distribution(ps)},
          {"video_fraction", distribution(vf)}};
}

// The model updater on the scene's clock: frames taken every refresh period (on its grid from
// the first frame, missed slots skipped as its thread does), published the model's delay later.
class SteppedUpdater {
 public:
  explicit SteppedUpdater(StationParts& p) : p_(p) {
    if (!p.updater) return;
    period_ns_ = std::llround(p.updater->config().refresh_period_s * 1e9);
    delay_ns_ = std::llround(p.updater->config().delay_s * 1e9);
  }
  void advance_to(int64_t now_ns) {
    if (!p_.updater) return;
    auto& clock = static_cast<render::SteppedLoopClock&>(*p_.updater_clock);
    if (!pending_ && (next_ns_ == 0 || now_ns >= next_ns_)) {
      if (next_ns_ == 0) next_ns_ = now_ns;
      clock.set_ns(now_ns);
      pending_ = p_.updater->take_update();
      finish_ns_ = now_ns + delay_ns_;
      while (next_ns_ <= now_ns) next_ns_ += period_ns_;
    }
    if (pending_ && now_ns >= finish_ns_) {
      clock.set_ns(now_ns);
      p_.updater->finish_update();
      pending_ = false;
    }
  }

 private:
  StationParts& p_;
  int64_t period_ns_ = 0, delay_ns_ = 0;
  int64_t next_ns_ = 0, finish_ns_ = 0;
  bool pending_ = false;
};

int score(const ScoreOptions& so) {
  namespace fs = std::filesystem;
  RunOptions o = so.station;
  o.headless = true;
  const std::string scene_path =
      scene_or_default(o.scene_path, "hybrid-station score", "no --scene");
  sim::Scene scene = sim::load_scene(scene_path);
  const double duration_s = scene.duration_s;
  const std::unique_ptr<StationParts> parts =
      assemble_from_scene(std::move(scene), o, SceneDevices::kStepped);
  StationParts& p = *parts;
  p.report.print(stdout);
  if (p.report.fatal()) {
    std::fprintf(stderr, "hybrid-station score: cannot start: %s\n",
                 p.report.missing_summary().c_str());
    return 3;
  }
  // The operator's cues (marking, guidance, HUD) are information, not errors: scored without.
  p.frame_config.marking.style = core::MarkingStyle::kNone;
  p.frame_config.draw_guidance = false;
  p.frame_config.max_rows = 0;

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (!fs::is_directory(o.out_dir, ec))
    throw std::runtime_error("--out " + o.out_dir + ": cannot create the directory");
  const std::string frames_dir = o.out_dir + "/frames";
  if (so.save_frames > 0) fs::create_directories(frames_dir, ec);

  const uint64_t frames = o.frames ? o.frames
                                   : static_cast<uint64_t>(std::llround(
                                         (o.seconds > 0.0 ? o.seconds : duration_s) * p.rate_hz));
  const int64_t epoch = p.stepped->epoch_ns;
  const int64_t period_ns = std::llround(1e9 / p.rate_hz);
  const int64_t scanout_ns = std::llround(p.scanout_ms * 1e6);
  std::printf("  score            %" PRIu64 " frames at %g Hz on the scene's clock, %s\n", frames,
              p.rate_hz, p.frame_config.rig.eye_count() == 2 ? "both eyes" : "one eye");
  std::printf("  scored without   marking, guidance and HUD%s\n",
              p.frame_config.lens ? "; before the lens pass" : "");
  std::fflush(stdout);

  // OpenCV's quality module allocates its large float images anew for every score; kept by the
  // allocator instead of returned to the system each time, they cost no page faults (which
  // took half the run's time).
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  render::SteppedLoopClock clock(epoch);
  render::CpuCompositor compositor(o.threads);
  std::vector<uint8_t> weights;
  compositor.record_video_weight(&weights);
  render::LatencyRecorder latency(static_cast<std::size_t>(frames));
  std::unique_ptr<PosePredictor> predictor = make_predictor(p.predictor);
  StationFrame frame(p.frame_config, p.calibrated_cameras(), *p.head, *predictor, compositor,
                     &p.model, clock, latency);
  if (p.updater) frame.set_model_updater(p.updater.get());
  SteppedUpdater updater(p);

  // The truth: the whole scene (moving objects placed at each display time), no effects.
  std::vector<std::unique_ptr<render::CpuCompositor>> truth_compositors, pure_compositors;
  for (int e = 0; e < 2; ++e) {
    truth_compositors.push_back(std::make_unique<render::CpuCompositor>(o.threads));
    pure_compositors.push_back(std::make_unique<render::CpuCompositor>(o.threads));
  }
  render::SyntheticScene truth_scene = p.simulation->model();
  const render::StereoRig& rig = p.frame_config.rig;
  const int eyes = rig.eye_count();
  std::vector<render::ImageRgba8> truth(static_cast<std::size_t>(eyes));
  std::vector<render::ImageRgba8> pure(static_cast<std::size_t>(eyes));
  for (int e = 0; e < eyes; ++e) {
    const core::Pinhole& eye = rig.eye[static_cast<std::size_t>(e)];
    truth[static_cast<std::size_t>(e)].allocate(eye.width, eye.height);
    pure[static_cast<std::size_t>(e)].allocate(eye.width, eye.height);
  }
  const std::vector<std::string> names = p.camera_names();

  std::vector<ScoreRow> rows;
  rows.reserve(static_cast<std::size_t>(frames) * static_cast<std::size_t>(eyes));
  p.start();
  const auto wall_start = std::chrono::steady_clock::now();
  double render_s = 0.0;
  uint64_t next_progress = std::max<uint64_t>(1, frames / 10);
  for (uint64_t k = 0; k < frames; ++k) {
    const int64_t start = epoch + static_cast<int64_t>(k) * period_ns;
    clock.set_ns(start);
    for (auto& cam : p.stepped->cameras) cam->advance_to(start);
    for (StationCamera& c : p.cameras)
      while (c.pipeline->process_one()) {
      }
    p.stepped->head->advance_to(start);
    p.head->pump();
    updater.advance_to(start);
    render::FrameTiming t;
    t.frame = k;
    t.start_ns = start;
    t.deadline_ns = start + period_ns;
    t.display_ns = t.deadline_ns + scanout_ns;
    t.dt_s = k ? 1e-9 * static_cast<double>(period_ns) : 0.0;
    const auto r0 = std::chrono::steady_clock::now();
    frame.tick(t);
    const double tick_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
    render_s += tick_s;

    const double t_display_s = 1e-9 * static_cast<double>(t.display_ns - epoch);
    p.simulation->place_objects(truth_scene, t_display_s);
    // The scene's tracker frame is the workspace (assemble_from_scene): the true head is the
    // motion itself, without the tracker's noise and drift.
    const core::Pose T_world_head = p.simulation->head().sample_at(t_display_s).T_tracker_head;
    const FrameRow& fr = frame.last_row();
    // The eyes are scored side by side (the truth render and the scores are most of the time);
    // each has its own compositor and writes only its own row.
    ScoreRow eye_rows[2];
    const auto score_eye = [&](int e) {
      const std::size_t ei = static_cast<std::size_t>(e);
      render::CompositeRequest req;
      req.scene = &truth_scene;
      req.eye = rig.eye[ei];
      req.T_world_eye = rig.T_world_eye(T_world_head, e);
      req.near_m = p.frame_config.near_m;
      req.marking.style = core::MarkingStyle::kNone;
      req.viewport = {0, 0, truth[ei].width, truth[ei].height};
      truth_compositors[ei]->draw(req, truth[ei]);
      const render::Viewport vp = rig.viewport(e);
      const render::ImageRgba8 shown = crop(frame.eyes_image(), vp);
      const std::size_t stride = static_cast<std::size_t>(frame.eyes_image().width);
      ScoreRow& r = eye_rows[ei];
      r.frame = k;
      r.t_s = t_display_s;
      r.eye = e;
      r.variant = fr.variant;
      r.camera = fr.camera >= 0 && static_cast<std::size_t>(fr.camera) < names.size()
                     ? names[static_cast<std::size_t>(fr.camera)]
                     : "";
      r.m = fr.m;
      r.w_video = fr.w_video;
      r.whole = score_image(shown, truth[ei]);
      const WeightSplit split =
          split_by_weight(shown, truth[ei],
                          weights.data() + static_cast<std::size_t>(vp.y) * stride + vp.x, stride);
      r.psnr_video_db = split.psnr_video_db;
      r.psnr_blend_db = split.psnr_blend_db;
      r.psnr_synthetic_db = split.psnr_synthetic_db;
      r.video_fraction = split.video_fraction;
      // The same frame (pose, model, camera and its frame) as pure model and as pure video.
      render::CompositeRequest view = frame.last_request(e);
      view.viewport = {0, 0, pure[ei].width, pure[ei].height};
      view.marking.style = core::MarkingStyle::kNone;
      view.mode = core::TransitionMode::kGlobalBlend;
      const drivers::Frame* video = view.video;
      view.video = nullptr;
      view.transition = {core::Variant::kSynthetic, 0.0, 1.0};
      pure_compositors[ei]->draw(view, pure[ei]);
      r.psnr_pure_synthetic_db = psnr_db(pure[ei], truth[ei]);
      if (video != nullptr && view.has_region) {
        view.video = video;
        view.transition = {core::Variant::kVideo, 1.0, 0.0};
        pure_compositors[ei]->draw(view, pure[ei]);
        r.psnr_pure_video_db = psnr_db(pure[ei], truth[ei]);
      }
      if (so.save_frames > 0 && k % so.save_frames == 0) {
        char number_text[32];
        std::snprintf(number_text, sizeof number_text, "%06" PRIu64, k);
        const std::string stem = frames_dir + "/" + number_text + "_eye" + std::to_string(e);
        cv::Mat bgr;
        rgba_to_bgr(shown, bgr);
        write_png_atomically(bgr, stem + "_shown.png");
        rgba_to_bgr(truth[ei], bgr);
        write_png_atomically(bgr, stem + "_truth.png");
      }
    };
    if (eyes == 2) {
      std::exception_ptr failed;
      std::thread other([&] {
        try {
          score_eye(1);
        } catch (...) {
          failed = std::current_exception();
        }
      });
      score_eye(0);
      other.join();
      if (failed) std::rethrow_exception(failed);
    } else {
      score_eye(0);
    }
    for (int e = 0; e < eyes; ++e) rows.push_back(std::move(eye_rows[e]));
    if (k + 1 >= next_progress || k + 1 == frames) {
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      std::printf("  progress         frame %" PRIu64 " of %" PRIu64
                  ", scene t = %.1f s, %.2f x "
                  "real time\n",
                  k + 1, frames, t_display_s, wall > 0.0 ? t_display_s / wall : 0.0);
      std::fflush(stdout);
      next_progress += std::max<uint64_t>(1, frames / 10);
    }
  }
  p.stop();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  const double scene_s = static_cast<double>(frames) / p.rate_hz;

  write_csv(rows, o.out_dir + "/score.csv");
  std::vector<const ScoreRow*> all, by_variant[3];
  for (const ScoreRow& r : rows) {
    all.push_back(&r);
    by_variant[static_cast<int>(r.variant)].push_back(&r);
  }
  nlohmann::json j;
  j["scene"] = scene_path;
  j["settings"] = {{"frames", frames},
                   {"rate_hz", p.rate_hz},
                   {"eyes", eyes},
                   {"eye_width", rig.eye[0].width},
                   {"eye_height", rig.eye[0].height},
                   {"transition", transition_mode_name(p.frame_config.transition.mode)},
                   {"m_t", p.frame_config.transition.m_t},
                   {"eps", p.frame_config.transition.eps},
                   {"predictor", p.predictor},
                   {"scored_without", "marking, guidance, HUD"}};
  j["overall"] = scores_of(all);
  std::vector<MSample> samples;
  for (const ScoreRow& r : rows)
    samples.push_back({r.m, r.psnr_pure_video_db, r.psnr_pure_synthetic_db});
  const MAgainstTruth mt = m_against_truth(samples);
  const auto or_null = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
  };
  j["m_against_truth"] = {
      {"eye_frames", mt.samples},
      {"spearman_m_vs_video_error", or_null(mt.spearman)},
      {"break_even_m", or_null(mt.break_even_m)},
      {"note", "an image metric (PSNR against the simulator's truth), not a user study"}};
  j["by_variant"] = {{"video", scores_of(by_variant[0])},
                     {"hybrid", scores_of(by_variant[1])},
                     {"synthetic", scores_of(by_variant[2])}};
  // Machine figures, beside the scores: they do not move the scene's clock.
  j["speed"] = {
      {"wall_s", wall_s},
      {"scene_s", scene_s},
      {"x_real_time", wall_s > 0.0 ? scene_s / wall_s : 0.0},
      {"render_ms_per_frame", frames ? 1e3 * render_s / static_cast<double>(frames) : 0.0}};
  write_text_atomically(j.dump(1) + "\n", o.out_dir + "/score.json");
  std::vector<ScorePoint> eye0;
  for (const ScoreRow& r : rows)
    if (r.eye == 0)
      eye0.push_back(
          {r.t_s, r.variant, r.whole.psnr_db, r.m, r.psnr_pure_video_db, r.psnr_pure_synthetic_db});
  write_png_atomically(draw_score_trace(eye0), o.out_dir + "/score_trace.png");
  write_png_atomically(draw_m_scatter(eye0, mt.break_even_m), o.out_dir + "/m_scatter.png");

  const nlohmann::json& ov = j["overall"];
  std::printf("score (%s)\n", scene_path.c_str());
  if (ov["psnr_db"].contains("mean"))
    std::printf("  PSNR mean %.2f dB, p5 %.2f dB; SSIM mean %.4f, p5 %.4f; GMSD mean %.4f\n",
                ov["psnr_db"]["mean"].get<double>(), ov["psnr_db"]["p5"].get<double>(),
                ov["ssim"]["mean"].get<double>(), ov["ssim"]["p5"].get<double>(),
                ov["gmsd"]["mean"].get<double>());
  std::printf(
      "  m against the truth: Spearman rho %.3f of m and the pure video view's error over "
      "%zu eye-frames; break-even m %s\n",
      mt.spearman, mt.samples,
      std::isfinite(mt.break_even_m) ? fmt("%.1f px", mt.break_even_m).c_str()
                                     : "none in the range");
  std::printf("  %" PRIu64
              " frames (%.1f s of scene) in %.1f s: %.2f x real time; the station's "
              "tick %.2f ms per frame on this machine\n",
              frames, scene_s, wall_s, wall_s > 0.0 ? scene_s / wall_s : 0.0,
              frames ? 1e3 * render_s / static_cast<double>(frames) : 0.0);
  for (const char* f : {"score.csv", "score.json", "score_trace.png", "m_scatter.png"})
    std::printf("  wrote %s/%s\n", o.out_dir.c_str(), f);
  if (so.save_frames > 0)
    std::printf("  wrote %s/NNNNNN_eyeE_{shown,truth}.png\n", frames_dir.c_str());
  return 0;
}

}  // namespace

int run_score(const ScoreOptions& options) {
  try {
    return score(options);
  } catch (const config::ConfigError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station score: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station score: %s\n", e.what());
    return 1;
  }
}

}  // namespace hd::station
