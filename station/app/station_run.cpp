#include "station/app/station_run.h"

#define GLFW_INCLUDE_NONE  // epoxy provides the GL declarations
#include <GLFW/glfw3.h>

#include <atomic>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/allocation_counter.h"
#include "drivers/camera_factory.h"
#include "render/compositor/cpu_compositor.h"
#include "render/gl/gl_compositor.h"
#include "render/latency/latency_recorder.h"
#include "render/loop/frame_loop.h"
#include "sim/scene/scene_file.h"
#include "station/app/camera_events.h"
#include "station/app/contact_sheet.h"
#include "station/app/frame_log.h"
#include "station/app/frame_recorder.h"
#include "station/app/frames_csv.h"
#include "station/app/model_tile.h"
#include "station/app/rate_holder.h"
#include "station/app/run_progress.h"
#include "station/app/run_stages.h"
#include "station/app/run_summary.h"
#include "station/app/run_work.h"
#include "station/app/scene_locator.h"
#include "station/app/station_parts.h"
#include "station/app/trace_plot.h"
#include "station/app/usability_log.h"
#include "station/prediction/predictor_by_name.h"
#include "station/selection/camera_need.h"

namespace hd::station {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
}

// Window keys, polled between frames (edge-triggered).
class KeyPoller {
 public:
  explicit KeyPoller(GLFWwindow* w) : window_(w) {}
  bool pressed(int key) {
    const bool down = glfwGetKey(window_, key) == GLFW_PRESS;
    bool& was = down_[key & 511];
    const bool edge = down && !was;
    was = down;
    return edge;
  }

 private:
  GLFWwindow* window_;
  bool down_[512] = {};
};

// The first frames would otherwise show the tracker origin (the predictor has nothing yet), not
// the operator's head. Cameras are not waited for: a frame without video is honestly synthetic.
// With a scene epoch ahead (--scene-epoch) the head's first sample comes at scene t = 0.
void wait_for_first_head_sample(drivers::PoseSource& head, render::LoopClock& clock,
                                int64_t scene_epoch_ns) {
  constexpr int64_t kPatience_ns = 2'000'000'000;
  const int64_t start = std::max(clock.now_ns(), scene_epoch_ns);
  while (head.latest().published() == 0 && !g_interrupted.load()) {
    if (clock.now_ns() - start > kPatience_ns) {
      std::printf("  note: no head sample from %s after 2 s: frames start at the tracker origin\n",
                  head.id().c_str());
      std::fflush(stdout);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Network cameras (--cameras-from) are waited for, up to `patience_s`, before the first frame:
// each one's first frame is reported with its time, and one still silent then is reported as not
// usable (its m is +inf until it streams). Nothing is shown meanwhile, so no frame of the run is
// synthetic only because the remote site was still starting.
void wait_for_network_cameras(const StationParts& p, render::LoopClock& clock) {
  std::vector<const StationCamera*> awaited;
  for (const StationCamera& c : p.cameras)
    if (c.awaited) awaited.push_back(&c);
  if (awaited.empty()) return;
  const int64_t start = clock.now_ns();
  const auto deadline = start + static_cast<int64_t>(p.camera_wait_s * 1e9);
  std::printf("  waiting up to %.0f s for the first frames of %zu network camera(s)\n",
              p.camera_wait_s, awaited.size());
  std::fflush(stdout);
  std::size_t left = awaited.size();
  while (left > 0 && !g_interrupted.load()) {
    for (const StationCamera*& c : awaited) {
      if (c == nullptr || c->pipeline->state() != drivers::SourceState::kStreaming) continue;
      std::printf("  camera %s: first frame %.2f s after the wait began\n", c->name.c_str(),
                  1e-9 * static_cast<double>(clock.now_ns() - start));
      std::fflush(stdout);
      c = nullptr;  // seen
      --left;
    }
    if (left == 0 || clock.now_ns() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  for (const StationCamera* c : awaited)
    if (c != nullptr)
      std::printf("  camera %s: no frame after %.0f s: not usable until it streams\n",
                  c->name.c_str(), p.camera_wait_s);
  std::fflush(stdout);
}

std::unique_ptr<StationParts> assemble(const RunOptions& o) {
  if (!o.config_path.empty()) {
    std::printf("hybrid-station run: station config %s (real devices)\n", o.config_path.c_str());
    return assemble_from_config(load_station_config(o.config_path), o);
  }
  const std::string scene_path =
      scene_or_default(o.scene_path, "hybrid-station run", "no --scene or --config");
  sim::Scene scene = sim::load_scene(scene_path);
  if (o.loop) scene.loop = true;
  return assemble_from_scene(std::move(scene), o);
}

int run(const RunOptions& o) {
  namespace fs = std::filesystem;
  std::unique_ptr<StationParts> parts = assemble(o);
  StationParts& p = *parts;
  p.report.print(stdout);
  if (p.report.fatal()) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station run: cannot start: %s\n",
                 p.report.missing_summary().c_str());
    return 3;
  }
  if (p.cameras.empty()) std::printf("  note: no camera is usable: every frame is synthetic\n");

  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (!fs::is_directory(o.out_dir, ec)) {
    std::fprintf(stderr, "hybrid-station run: --out %s: cannot create the directory\n",
                 o.out_dir.c_str());
    return 1;
  }

  // Run length, and everything sized by it.
  const double seconds = o.frames ? 0.0 : (o.seconds > 0.0 ? o.seconds : p.default_seconds);
  // With a fixed scene epoch a run of the scene's length ends at scene t = its duration,
  // however long the start (the wait for the remote site's cameras) took.
  const bool until_scene_end = p.scene_epoch_ns != 0 && !o.frames && o.seconds <= 0.0;
  const double expected_frames =
      o.frames ? static_cast<double>(o.frames)
               : (seconds > 0.0 ? seconds * p.rate_hz * 1.05 + 16.0 : 3600.0 * p.rate_hz);
  const std::size_t log_rows =
      std::min<std::size_t>(o.max_log_rows, static_cast<std::size_t>(expected_frames));
  p.frame_config.max_rows = 0;

  const bool windowed = !o.headless;
  std::unique_ptr<render::Compositor> compositor;
  render::GlCompositor* gl = nullptr;
  std::string compositor_name;
  if (o.gl || windowed) {
    render::gl::WindowOptions wo;
    wo.width = p.frame_config.picture_width();
    wo.height = p.frame_config.picture_height();
    if (p.frame_config.lens) {  // the HMD's own display: its native panel mode
      wo.mode_width = p.frame_config.lens->panel_width();
      wo.mode_height = p.frame_config.lens->panel_height();
    }
    wo.headless = o.headless;
    wo.monitor = windowed ? p.monitor : -1;
    std::unique_ptr<render::GlCompositor> glc;
    try {
      glc = std::make_unique<render::GlCompositor>(wo);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string(e.what()) +
                               (windowed ? " (without a display, pass --headless)" : ""));
    }
    compositor_name = "OpenGL (" + glc->renderer() + ", " + glc->version() + ")";
    gl = glc.get();
    compositor = std::move(glc);
  } else {
    compositor = std::make_unique<render::CpuCompositor>(o.threads);
    compositor_name = "CPU reference (" + std::to_string(o.threads) + " thread(s))";
  }
  std::printf("  compositor       %s, %s\n", compositor_name.c_str(),
              windowed ? (p.monitor >= 0 ? "fullscreen"
                                         : "windowed; keys: R re-centre, G stage graph, Esc/Q quit")
                       : "headless");
  if (gl) std::printf("  display          %s\n", gl->window().description().c_str());
  if (o.frames)
    std::printf("  run              %" PRIu64 " frames\n", o.frames);
  else if (until_scene_end)
    std::printf("  run              until scene t = %.1f s\n", seconds);
  else if (seconds > 0.0)
    std::printf("  run              %.1f s\n", seconds);
  else
    std::printf("  run              until Esc/Q (or Ctrl-C)\n");
  RateHolder rates(p.rate_hz, o.rate_policy == "hold", stdout);
  std::printf("  rate             %s\n", rates.start_line().c_str());
  if (!o.video_path.empty() && rates.holds())
    std::printf(
        "  note: --video is written at %.1f fps: frames at a held lower rate play faster "
        "(--rate-policy fixed keeps them in time)\n",
        p.rate_hz);
  std::printf("  outputs          %s/\n", o.out_dir.c_str());
  std::fflush(stdout);

  std::unique_ptr<station::PosePredictor> predictor = make_predictor(p.predictor);
  render::MonotonicLoopClock clock;
  render::LatencyRecorder latency(log_rows);
  const std::vector<std::string> camera_names = p.camera_names();
  station::StationFrame frame(p.frame_config, p.calibrated_cameras(), *p.head, *predictor,
                              *compositor, &p.model, clock, latency);
  if (p.updater) frame.set_model_updater(p.updater.get());
  FrameLog log(log_rows);
  const int width = p.frame_config.picture_width();
  ThumbnailSet thumbs(96, std::min(width, 320), width, p.frame_config.picture_height(),
                      std::max<uint64_t>(1, static_cast<uint64_t>(expected_frames / 96.0)));
  FrameRecorderOptions ro;
  ro.video_path = o.video_path;
  ro.video_fps = p.rate_hz;
  ro.png_every = o.png_every;
  ro.png_dir = o.out_dir;
  ro.thumbnails = &thumbs;
  FrameRecorder recorder(width, p.frame_config.picture_height(), ro);
  RunWork work(frame, latency, log, recorder, o.warmup);
  render::FrameLoop loop(
      render::FrameLoopConfig{p.rate_hz, static_cast<int64_t>(p.scanout_ms * 1e6), true}, clock);

  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  std::unique_ptr<KeyPoller> keys;
  if (gl && windowed) keys = std::make_unique<KeyPoller>(gl->window().handle());

  core::reset_counted_allocations();
  p.start();
  wait_for_first_head_sample(*p.head, clock, p.scene_epoch_ns);
  wait_for_network_cameras(p, clock);
  const int64_t start_ns = clock.now_ns();
  rates.set_start(start_ns);
  RunStages stages(p.cameras.size());
  uint64_t recorded = latency.total_recorded();
  const int64_t end_ns = until_scene_end ? p.scene_epoch_ns + static_cast<int64_t>(seconds * 1e9)
                                         : start_ns + static_cast<int64_t>(seconds * 1e9);
  if (p.scene_epoch_ns != 0) {
    std::printf("  first frame at scene t = %.3f s\n",
                1e-9 * static_cast<double>(start_ns - p.scene_epoch_ns));
    std::fflush(stdout);
  }
  int64_t next_hud_ns = start_ns;
  std::string hud;
  bool show_graph = o.hud_graph;
  RunProgress progress(o.progress_s, stdout, start_ns);
  // Format changes are reported when they happen, not only as a count at the end.
  CameraEventLog camera_events(stdout, start_ns);
  // So is every camera becoming unusable (too old, not streaming) and usable again.
  UsabilityLog usability(stdout, start_ns, p.cameras.size());
  // Bandwidth follows the view (docs/network.md): network cameras the view cannot use soon are
  // told so and sent at a low rate; the others (and every camera of an old sender) at full rate.
  station::CameraNeedParams need_params;
  need_params.m_t = p.frame_config.transition.m_t;
  station::CameraNeedPolicy need(p.cameras.size(), need_params);
  if (p.updater)  // the pairs it reconstructs from need frames of one exposure from both
    for (const station::ModelStereoPair& pair : p.updater->config().stereo_pairs) {
      if (pair.left < p.cameras.size()) need.keep(pair.left);
      if (pair.right < p.cameras.size()) need.keep(pair.right);
    }
  for (;;) {
    if (o.frames && loop.frames() >= o.frames) break;
    if (!o.frames && seconds > 0.0 && clock.now_ns() >= end_ns) break;
    if (g_interrupted.load()) break;
    loop.tick(work);
    // Between frames, outside the counted tick: the rate, progress, the HUD text (OpenCV may
    // allocate), the keys.
    const int64_t now = clock.now_ns();
    rates.after_frame(loop, now);
    if (latency.total_recorded() > recorded) {  // the frame's record (not one of warm-up)
      recorded = latency.total_recorded();
      stages.after_frame(latency.at(latency.size() - 1), frame.last_row().camera,
                         p.updater ? &p.updater->models().latest() : nullptr, now);
    }
    if (p.updater) {
      const station::ModelUpdaterStats ms = p.updater->stats();
      progress.model_done(ms.updates, ms.reconstructions);
    }
    progress.frame_done(frame.last_row().variant, loop.frames(), loop.missed_deadlines(), now);
    camera_events.poll(p.cameras);
    camera_events.poll_calibrations(p.cameras);
    usability.poll(frame, camera_names);
    need.update(frame.view_m(), frame.selector().current(), now);
    for (std::size_t i = 0; i < p.cameras.size(); ++i)
      if (drivers::CameraLink* link = p.cameras[i].link) link->set_view_needed(need.needed(i));
    if (now >= next_hud_ns) {
      next_hud_ns = now + 500'000'000;
      const station::FrameRow& r = frame.last_row();
      hud.assign(variant_name(r.variant));
      hud += "  ";
      hud.append(latency.hud_line());
      const std::string stage_text = stages.hud_text(r.camera, camera_names, now);
      if (!stage_text.empty()) hud += " | " + stage_text;
      stages.sample_graph(r.camera, now);
      frame.set_hud(hud, show_graph ? stages.graph(camera_names) : render::HudGraph{});
    }
    if (keys) {
      gl->window().poll_events();
      if (keys->pressed(GLFW_KEY_R)) p.head->request_recentre();
      if (keys->pressed(GLFW_KEY_G)) {  // the stage graph: at once, not at the next HUD update
        show_graph = !show_graph;
        next_hud_ns = now;
      }
      if (keys->pressed(GLFW_KEY_ESCAPE) || keys->pressed(GLFW_KEY_Q) ||
          gl->window().should_close())
        break;
    }
  }
  const double loop_s = 1e-9 * static_cast<double>(clock.now_ns() - start_ns);
  const uint64_t allocations = core::counted_allocations();
  p.stop();
  camera_events.poll(p.cameras);
  camera_events.poll_calibrations(p.cameras);
  usability.poll(frame, camera_names);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  const FrameRecorderStats rec = recorder.finish();

  RunSummary s;
  s.source = p.source_kind + " " + p.source_file;
  s.frames = loop.frames();
  s.seconds = loop_s;
  s.rate_hz = p.rate_hz;
  s.rate_policy = o.rate_policy;
  s.rates = rates.rates();
  s.rate_changes = rates.changes();
  s.missed_deadlines = loop.missed_deadlines();
  s.skipped_slots = loop.skipped_slots();
  s.mtp_swap = latency.stats(render::LatencyMetric::kMotionToSwap);
  s.mtp_display = latency.stats(render::LatencyMetric::kMotionToDisplay);
  s.video_age = latency.stats(render::LatencyMetric::kVideoAge);
  s.model_age = latency.stats(render::LatencyMetric::kModelAge);
  s.render = latency.stats(render::LatencyMetric::kRender);
  for (const FrameLogRow& r : log) {
    ++s.variant_frames[static_cast<int>(r.decision.variant)];
    s.guidance_frames += r.decision.guidance;
  }
  s.camera_switches = frame.selector().switches();
  const std::vector<uint64_t> shown = frame.frames_fetched();
  for (std::size_t i = 0; i < p.cameras.size(); ++i) {
    const StationCamera& c = p.cameras[i];
    RunSummary::Camera& out = s.cameras.emplace_back();
    out.name = c.name;
    out.frames_shown = shown[i];
    out.frames_rejected = c.pipeline->rejected();
    out.frames_lost = c.pipeline->device_dropped_frames();
    out.unusable = usability.intervals()[i];
    out.stages = stage_figures(stages.video(i));
    if (c.link == nullptr) continue;
    RunSummary::NetworkCamera& n = out.network.emplace();
    static_cast<drivers::LinkReport&>(n) = c.link->link_report();
    n.need_changes = need.changes(i);
    const int64_t revision = c.pipeline->stream_revision();
    const std::string& file = c.description.calibration_file;
    n.calibration = revision >= 0  ? "stream (revision " + std::to_string(revision) + ")"
                    : file.empty() ? "none (no calibration arrived: never shown)"
                                   : "file " + file;
    n.frames_uncalibrated = c.pipeline->uncalibrated();
  }
  s.camera_events = camera_events.events();
  s.cameras_from = p.cameras_from;
  s.scene_epoch = p.scene_epoch_text;
  if (p.scene_epoch_ns != 0)
    s.first_frame_scene_s = 1e-9 * static_cast<double>(start_ns - p.scene_epoch_ns);
  s.frames_stale_blocked = frame.frames_stale_blocked();
  s.pose_accepted = frame.pose_history().accepted();
  s.pose_rejected = frame.pose_history().rejected() + p.head->rejected_reports();
  s.recentres = p.head->recentres();
  s.tracker_resets = p.head->tracker_resets();
  s.model_updates = p.updater ? p.updater->stats().updates : 0;
  s.model_stages = stage_figures(stages.model());
  s.reconstructions = p.updater ? p.updater->stats().reconstructions : 0;
  s.reconstructions_refused = p.updater ? p.updater->stats().reconstructions_refused : 0;
  s.allocations_after_warmup = allocations;
  s.warmup_frames = o.warmup;
  s.log_rows = log.size();
  s.log_rows_dropped = log.dropped();
  s.video_frames = rec.video_frames;
  s.png_frames = rec.png_frames;
  s.recorder_dropped = rec.dropped;
  s.recorder_error = rec.error;

  const std::string dir = o.out_dir + "/";
  latency.write_csv(dir + "latency.csv");
  latency.write_png(dir + "latency.png");
  write_frames_csv(log, camera_names, dir + "frames.csv");
  s.outputs = {dir + "latency.csv", dir + "latency.png", dir + "frames.csv"};
  if (log.size() > 0) {
    write_trace_png(log, p.frame_config.transition, dir + "trace.png");
    s.outputs.push_back(dir + "trace.png");
  }
  if (thumbs.size() > 0 && p.updater && !p.cameras.empty()) {
    // The newest model (the loop is over: this thread is the mailbox's consumer now), seen from
    // the camera farthest from the first one (in the default scene cam1, beside the rig, so the
    // reconstruction shows as a surface, not as the picture it was measured from), its
    // reconstructed part tinted.
    p.updater->models().fetch();
    const station::ModelSnapshot& snap = p.updater->models().latest();
    const std::vector<drivers::CalibratedCamera> cams = p.calibrated_cameras();
    std::size_t view = 0;
    for (std::size_t i = 1; i < cams.size(); ++i)
      if ((cams[i].T_world_real.t - cams[0].T_world_real.t).norm() >
          (cams[view].T_world_real.t - cams[0].T_world_real.t).norm())
        view = i;
    // (Cameras calibrated from a stream have no fixed p_c here; the pairs that reconstruct
    // need files, so the tile's camera has one whenever there is a reconstruction.)
    if (snap.scene.meshes.size() > snap.prior_meshes && cams[view].p_c.valid())
      thumbs.set_extra_tile(
          station::render_model_tile(snap, cams[view].p_c, cams[view].T_world_real),
          station::model_tile_label(snap));
  }
  if (thumbs.size() > 0) {
    write_contact_sheet(thumbs, dir + "contact_sheet.png", o.contact_tiles);
    s.outputs.push_back(dir + "contact_sheet.png");
  }
  if (!o.video_path.empty() && rec.error.empty()) s.outputs.push_back(o.video_path);
  if (o.png_every) s.outputs.push_back(dir + "frame_*.png");
  s.outputs.push_back(dir + "summary.json");
  write_summary_json(s, dir + "summary.json");
  print_summary(s, stdout);
  return rec.error.empty() ? 0 : 1;
}

}  // namespace

int run_station(const RunOptions& o) {
  int rc = 1;
  try {
    rc = run(o);
  } catch (const config::ConfigError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station run: %s\n", e.what());
    rc = 2;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "hybrid-station run: %s\n", e.what());
    rc = 1;
  }
  drivers::shutdown_camera_drivers();
  return rc;
}

}  // namespace hd::station
