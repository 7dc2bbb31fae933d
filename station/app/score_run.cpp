#include "station/app/score_run.h"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
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
#include "station/app/score_outputs.h"
#include "station/app/score_pictures.h"
#include "station/app/score_plots.h"
#include "station/app/score_sweep.h"
#include "station/app/station_config.h"
#include "station/app/station_parts.h"
#include "station/app/stepped_model_updater.h"
#include "station/prediction/predictor_by_name.h"
#include "station/score/image_scores.h"
#include "station/score/m_against_truth.h"
#include "station/score/transition_tuning.h"

namespace hd::station {
namespace {

render::ImageRgba8 crop(const render::ImageRgba8& im, const render::Viewport& vp) {
  render::ImageRgba8 out;
  out.allocate(vp.width, vp.height);
  for (int y = 0; y < vp.height; ++y)
    std::copy_n(im.row(vp.y + y) + 4 * vp.x, 4 * vp.width, out.row(y));
  return out;
}

struct CannotStart : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace

ScoreFigures score_scene(sim::Scene scene, const std::string& scene_path, const ScoreOptions& so) {
  namespace fs = std::filesystem;
  RunOptions o = so.station;
  o.headless = true;
  const double duration_s = scene.duration_s;
  const std::unique_ptr<StationParts> parts =
      assemble_from_scene(std::move(scene), o, SceneDevices::kStepped);
  StationParts& p = *parts;
  if (!so.quiet) p.report.print(stdout);
  if (p.report.fatal()) throw CannotStart("cannot start: " + p.report.missing_summary());
  // The operator's cues (marking, guidance, HUD) are information, not errors: scored without.
  p.frame_config.marking.style = core::MarkingStyle::kNone;
  p.frame_config.draw_guidance = false;
  p.frame_config.max_rows = 0;

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (!fs::is_directory(o.out_dir, ec))
    throw std::runtime_error("--out " + o.out_dir + ": cannot create the directory");
  const std::string frames_dir = o.out_dir + "/frames";
  // --error-maps alone keeps a map of every 90th frame (one a second at the default rate).
  const uint64_t save_every = so.save_frames > 0 ? so.save_frames : (so.error_maps ? 90 : 0);
  if (save_every > 0) fs::create_directories(frames_dir, ec);

  const uint64_t frames = o.frames ? o.frames
                                   : static_cast<uint64_t>(std::llround(
                                         (o.seconds > 0.0 ? o.seconds : duration_s) * p.rate_hz));
  const int64_t epoch = p.stepped->epoch_ns;
  const int64_t period_ns = std::llround(1e9 / p.rate_hz);
  const int64_t scanout_ns = std::llround(p.scanout_ms * 1e6);
  if (!so.quiet) {
    std::printf("  score            %" PRIu64 " frames at %g Hz on the scene's clock, %s\n", frames,
                p.rate_hz, p.frame_config.rig.eye_count() == 2 ? "both eyes" : "one eye");
    std::printf("  scored without   marking, guidance and HUD%s\n",
                p.frame_config.lens ? "; before the lens pass" : "");
    std::fflush(stdout);
  }

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
  SteppedModelUpdater updater(p);

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
  std::vector<render::ImageRgba8> pure_model(static_cast<std::size_t>(eyes));
  std::vector<std::vector<float>> positions(static_cast<std::size_t>(eyes));
  std::vector<BlendErrorModel> error_models(static_cast<std::size_t>(eyes));
  for (int e = 0; e < eyes; ++e) {
    const std::size_t ei = static_cast<std::size_t>(e);
    const core::Pinhole& eye = rig.eye[ei];
    truth[ei].allocate(eye.width, eye.height);
    pure[ei].allocate(eye.width, eye.height);
    pure_compositors[ei]->record_model_only(&pure_model[ei]);
    pure_compositors[ei]->record_video_positions(&positions[ei]);
  }
  // Every candidate m_t and eps replayed over this run's frames, the run's own among them (its
  // replay is checked against the pictures the station drew).
  std::vector<TuningCandidate> grid = TransitionTuner::default_grid();
  const core::TransitionParams& own = p.frame_config.transition;
  grid.push_back({own.mode, own.m_t, own.eps});
  const std::size_t own_candidate = grid.size() - 1;
  TransitionTuner tuner(grid, own);
  std::vector<std::vector<double>> tuning_scores(static_cast<std::size_t>(eyes));
  const std::vector<std::string> names = p.camera_names();
  // The contact sheet: eye 0 of six frames spread over the run.
  std::vector<uint64_t> sheet_frames;
  for (uint64_t i = 0; i < 6 && frames > 0 && !so.quiet; ++i) {
    const uint64_t f = frames > 1 ? i * (frames - 1) / 5 : 0;
    if (sheet_frames.empty() || sheet_frames.back() != f) sheet_frames.push_back(f);
  }
  std::size_t sheet_next = 0;
  std::vector<SheetRow> sheet;

  std::vector<ScoreRow> rows;
  rows.reserve(static_cast<std::size_t>(frames) * static_cast<std::size_t>(eyes));
  p.start();
  const auto wall_start = std::chrono::steady_clock::now();
  // Where the machine's time goes, per stage (CLOCK_MONOTONIC; never the scene's clock).
  double devices_s = 0.0, pipelines_s = 0.0, model_s = 0.0, render_s = 0.0, scoring_s = 0.0;
  const auto timed = [](double& total, auto&& work) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  // The stepped cameras (each renders with its own renderer); cameras_s is kept by one thread
  // at a time.
  double cameras_s = 0.0;
  const auto advance_cameras = [&](int64_t to_ns) {
    timed(cameras_s, [&] {
      for (auto& cam : p.stepped->cameras) cam->advance_to(to_ns);
    });
  };
  uint64_t next_progress = std::max<uint64_t>(1, frames / 10);
  for (uint64_t k = 0; k < frames; ++k) {
    const int64_t start = epoch + static_cast<int64_t>(k) * period_ns;
    clock.set_ns(start);
    // The cameras were advanced to this frame's start beside the last frame's scoring.
    if (k == 0) advance_cameras(start);
    timed(devices_s, [&] {
      p.stepped->head->advance_to(start);
      p.head->pump();
    });
    timed(pipelines_s, [&] {
      for (StationCamera& c : p.cameras)
        while (c.pipeline->process_one()) {
        }
    });
    timed(model_s, [&] { updater.advance_to(start); });
    render::FrameTiming t;
    t.frame = k;
    t.start_ns = start;
    t.deadline_ns = start + period_ns;
    t.display_ns = t.deadline_ns + scanout_ns;
    t.dt_s = k ? 1e-9 * static_cast<double>(period_ns) : 0.0;
    timed(render_s, [&] { frame.tick(t); });
    const auto scoring_start = std::chrono::steady_clock::now();
    // The remote site renders the next frame's camera pictures meanwhile: they go only into the
    // cameras' own mailboxes, which nothing reads until the pipelines' next step.
    std::exception_ptr cameras_failed;
    std::thread next_cameras;
    if (k + 1 < frames)
      next_cameras = std::thread([&, next = start + period_ns] {
        try {
          advance_cameras(next);
        } catch (...) {
          cameras_failed = std::current_exception();
        }
      });
    struct Join {
      std::thread& t;
      ~Join() {
        if (t.joinable()) t.join();
      }
    } join_cameras{next_cameras};

    const double t_display_s = 1e-9 * static_cast<double>(t.display_ns - epoch);
    p.simulation->place_objects(truth_scene, t_display_s);
    // The scene's tracker frame is the workspace (assemble_from_scene): the true head is the
    // motion itself, without the tracker's noise and drift.
    const core::Pose T_world_head = p.simulation->head().sample_at(t_display_s).T_tracker_head;
    const FrameRow& fr = frame.last_row();
    // The eyes are scored side by side (the truth render and the scores are most of the time);
    // each has its own compositor and writes only its own row.
    ScoreRow eye_rows[2];
    tuner.begin_frame(fr.m, t.dt_s, fr.w_cap);
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
      const double bound_ms = so.age_bound_ms;
      r.old_fraction = (fr.video_age_ms > bound_ms ? split.video_dominant_fraction : 0.0) +
                       (fr.model_age_ms > bound_ms ? 1.0 - split.video_dominant_fraction : 0.0);
      // The same frame (pose, model, camera and its frame) as pure video at global weight 1 and,
      // from the same draw, as pure model.
      render::CompositeRequest view = frame.last_request(e);
      view.viewport = {0, 0, pure[ei].width, pure[ei].height};
      view.marking.style = core::MarkingStyle::kNone;
      view.mode = core::TransitionMode::kGlobalBlend;
      view.transition = {core::Variant::kVideo, 1.0, 0.0};
      const bool has_video = view.video != nullptr && view.has_region;
      pure_compositors[ei]->draw(view, pure[ei]);
      BlendErrorModel& model = error_models[ei];
      model.build(truth[ei], pure_model[ei], pure[ei], has_video ? positions[ei].data() : nullptr,
                  has_video ? view.video->width : 0, has_video ? view.video->height : 0);
      // The pure views' errors are the error model at weights 0 and 1 (the same integer sums).
      r.psnr_pure_synthetic_db = model.psnr_db(core::TransitionMode::kGlobalBlend, 0.0);
      if (has_video) r.psnr_pure_video_db = model.psnr_db(core::TransitionMode::kGlobalBlend, 1.0);
      tuner.score_eye(model, tuning_scores[ei]);
      const bool save = save_every > 0 && k % save_every == 0;
      const bool on_sheet =
          e == 0 && sheet_next < sheet_frames.size() && sheet_frames[sheet_next] == k;
      if (save || on_sheet) {
        cv::Mat shown_bgr, truth_bgr;
        rgba_to_bgr(shown, shown_bgr);
        rgba_to_bgr(truth[ei], truth_bgr);
        const cv::Mat error = error_map(shown, truth[ei]);
        if (save) {
          char number_text[32];
          std::snprintf(number_text, sizeof number_text, "%06" PRIu64, k);
          const std::string stem = frames_dir + "/" + number_text + "_eye" + std::to_string(e);
          if (so.save_frames > 0) {
            write_png_atomically(shown_bgr, stem + "_shown.png");
            write_png_atomically(truth_bgr, stem + "_truth.png");
          }
          if (so.error_maps) {
            cv::Mat with_scale;
            cv::vconcat(error, error_legend(error.cols), with_scale);
            write_png_atomically(with_scale, stem + "_error.png");
          }
        }
        if (on_sheet) {
          // Half size on the sheet (an overview: 18 photographic tiles at full size were a
          // 4.5 MB PNG); --save-frames and --error-maps keep the full pictures.
          const auto half = [](const cv::Mat& m) {
            cv::Mat out;
            cv::resize(m, out, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
            return out;
          };
          sheet.push_back({fmt("frame %.0f  t %.2f s  ", static_cast<double>(k), t_display_s) +
                               variant_name(r.variant) + fmt("  %.1f dB", r.whole.psnr_db),
                           half(shown_bgr), half(truth_bgr), half(error)});
        }
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
    if (sheet_next < sheet_frames.size() && sheet_frames[sheet_next] == k) ++sheet_next;
    tuner.end_frame(tuning_scores, error_models[0].has_video());
    if (next_cameras.joinable()) next_cameras.join();
    if (cameras_failed) std::rethrow_exception(cameras_failed);
    scoring_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - scoring_start).count();
    if (!so.quiet && (k + 1 >= next_progress || k + 1 == frames)) {
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
  const auto per_frame_ms = [&](double s) {
    return frames ? 1e3 * s / static_cast<double>(frames) : 0.0;
  };

  write_score_csv(rows, o.out_dir + "/score.csv");
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
                   {"age_bound_ms", so.age_bound_ms},
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
  // The replay of the run's own transition against the pictures the station drew: how far the
  // tuning's scores can be trusted.
  const std::vector<double>& replayed = tuner.trace(own_candidate);
  double diff_sum = 0.0, diff_max = 0.0;
  for (std::size_t i = 0; i < rows.size() && i < replayed.size(); ++i) {
    const double d = std::abs(replayed[i] - rows[i].whole.psnr_db);
    diff_sum += d;
    diff_max = std::max(diff_max, d);
  }
  const double diff_mean = rows.empty() ? 0.0 : diff_sum / static_cast<double>(rows.size());
  write_tuning_csv(tuner.results(), o.out_dir + "/tuning.csv");
  nlohmann::json best = nlohmann::json::object();
  for (core::TransitionMode mode :
       {core::TransitionMode::kAbrupt, core::TransitionMode::kGlobalBlend,
        core::TransitionMode::kPerPixel}) {
    const TuningResult b = tuner.best(mode);
    best[transition_mode_name(mode)] = {{"m_t", b.candidate.m_t},
                                        {"eps", b.candidate.eps},
                                        {"psnr_mean_db", b.psnr_mean_db},
                                        {"psnr_p5_db", b.p5_db},
                                        {"video_share", b.video_share}};
  }
  const TuningResult own_result = tuner.results()[own_candidate];
  j["tuning"] = {
      {"candidates", grid.size()},
      {"best", best},
      {"this_run",
       {{"m_t", own.m_t}, {"eps", own.eps}, {"psnr_mean_db_replayed", own_result.psnr_mean_db}}},
      {"replay_check",
       {{"mean_abs_db", diff_mean},
        {"max_abs_db", diff_max},
        {"note", "the run's own transition replayed, against the PSNR of the pictures it drew"}}},
      {"grid", "tuning.csv"}};
  j["by_variant"] = {{"video", scores_of(by_variant[0])},
                     {"hybrid", scores_of(by_variant[1])},
                     {"synthetic", scores_of(by_variant[2])}};
  // Machine figures, beside the scores: they do not move the scene's clock.
  j["speed"] = {{"wall_s", wall_s},
                {"scene_s", scene_s},
                {"x_real_time", wall_s > 0.0 ? scene_s / wall_s : 0.0},
                {"render_ms_per_frame", per_frame_ms(render_s)},
                {"ms_per_frame",
                 {{"cameras_beside_scoring", per_frame_ms(cameras_s)},
                  {"head_tracker", per_frame_ms(devices_s)},
                  {"camera_pipelines", per_frame_ms(pipelines_s)},
                  {"model_updater", per_frame_ms(model_s)},
                  {"station_tick", per_frame_ms(render_s)},
                  {"scoring", per_frame_ms(scoring_s)}}}};
  write_text_atomically(j.dump(1) + "\n", o.out_dir + "/score.json");
  ScoreFigures figures;
  const nlohmann::json& ov = j["overall"];
  figures.eye_frames = rows.size();
  if (ov["psnr_db"].contains("mean")) {
    figures.psnr_mean_db = ov["psnr_db"]["mean"].get<double>();
    figures.psnr_p5_db = ov["psnr_db"]["p5"].get<double>();
    figures.ssim_mean = ov["ssim"]["mean"].get<double>();
    figures.ssim_p5 = ov["ssim"]["p5"].get<double>();
  }
  figures.video_share = rows.empty()
                            ? 0.0
                            : static_cast<double>(by_variant[0].size() + by_variant[1].size()) /
                                  static_cast<double>(rows.size());
  figures.tick_ms = per_frame_ms(render_s);
  figures.x_real_time = wall_s > 0.0 ? scene_s / wall_s : 0.0;
  if (so.quiet) return figures;
  std::vector<ScorePoint> eye0;
  for (const ScoreRow& r : rows)
    if (r.eye == 0)
      eye0.push_back(
          {r.t_s, r.variant, r.whole.psnr_db, r.m, r.psnr_pure_video_db, r.psnr_pure_synthetic_db});
  write_png_atomically(draw_score_trace(eye0), o.out_dir + "/score_trace.png");
  write_png_atomically(draw_m_scatter(eye0, mt.break_even_m), o.out_dir + "/m_scatter.png");

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
  std::printf(
      "  best transition by mean PSNR over %zu candidates (replay within %.3f dB mean, "
      "%.3f dB max of the pictures drawn):\n",
      grid.size(), diff_mean, diff_max);
  for (const auto& [mode, b] : best.items())
    std::printf(
        "    %-12s m_t %5.1f px, eps %4.1f px: %.2f dB mean (this run's %.1f / %.1f: "
        "%.2f dB)\n",
        mode.c_str(), b["m_t"].get<double>(), b["eps"].get<double>(),
        b["psnr_mean_db"].get<double>(), own.m_t, own.eps, own_result.psnr_mean_db);
  std::printf("  %" PRIu64
              " frames (%.1f s of scene) in %.1f s: %.2f x real time; the station's "
              "tick %.2f ms per frame on this machine\n",
              frames, scene_s, wall_s, wall_s > 0.0 ? scene_s / wall_s : 0.0,
              per_frame_ms(render_s));
  std::printf(
      "  ms per frame     head tracker %.2f, camera pipelines %.2f, model updater %.2f, "
      "station tick %.2f, scoring (truth, pure views, scores; eyes side by side) %.2f; "
      "the simulated cameras %.2f beside the scoring\n",
      per_frame_ms(devices_s), per_frame_ms(pipelines_s), per_frame_ms(model_s),
      per_frame_ms(render_s), per_frame_ms(scoring_s), per_frame_ms(cameras_s));
  for (const char* f :
       {"score.csv", "score.json", "score_trace.png", "m_scatter.png", "tuning.csv"})
    std::printf("  wrote %s/%s\n", o.out_dir.c_str(), f);
  if (!sheet.empty()) {
    write_png_atomically(score_contact_sheet(sheet), o.out_dir + "/score_sheet.png");
    std::printf("  wrote %s/score_sheet.png (shown | truth | error of %zu frames, eye 0)\n",
                o.out_dir.c_str(), sheet.size());
  }
  if (so.save_frames > 0)
    std::printf("  wrote %s/NNNNNN_eyeE_{shown,truth}.png\n", frames_dir.c_str());
  if (so.error_maps)
    std::printf("  wrote %s/NNNNNN_eyeE_error.png (largest channel error, 0..%d DN)\n",
                frames_dir.c_str(), kErrorMapFullScaleDn);
  return figures;
}

int run_score(const ScoreOptions& options) {
  try {
    if (options.sweep) return run_score_sweep(options);
    const std::string scene_path =
        scene_or_default(options.station.scene_path, "hybrid-station score", "no --scene");
    score_scene(sim::load_scene(scene_path), scene_path, options);
    return 0;
  } catch (const config::ConfigError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station score: %s\n", e.what());
    return 2;
  } catch (const CannotStart& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station score: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station score: %s\n", e.what());
    return 1;
  }
}

}  // namespace hd::station
