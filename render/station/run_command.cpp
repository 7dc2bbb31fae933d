// hybrid-station run: the fixed-rate loop on a simulated scene (mock camera + mock head tracker),
// CPU compositor (or GL with --gl), writing latency and per-frame decisions.
#define GLFW_INCLUDE_NONE  // epoxy provides the GL declarations
#include <GLFW/glfw3.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/allocation_counter.h"
#include "drivers/mock/mock_camera.h"
#include "drivers/mock/mock_pose_source.h"
#include "render/compositor/cpu_compositor.h"
#include "render/gl/gl_compositor.h"
#include "render/latency/latency_recorder.h"
#include "render/loop/station_frame.h"
#include "render/prediction/constant_velocity_predictor.h"
#include "render/prediction/kalman_predictor.h"
#include "render/station/command.h"

// The summary counts allocations on the render thread inside a tick (hd_allocation_counter).

namespace hd::station {
namespace {

using render::FrameRow;

struct RunOptions {
  bool headless = false;
  bool gl = false;
  uint64_t frames = 600;
  double rate_hz = 90.0;
  std::string out_dir;
  bool mono = false;
  int eye_width = 480, eye_height = 400;
  std::string predictor = "kalman";
  double scanout_ms = 2.0;
  int threads = 1;
  int cameras = 2;
  double m_t = 40.0, eps = 10.0;
  uint64_t warmup = 30;
};

// --- The built-in scene: a back wall, a floor and a box, all textured. ---
render::ImageRgba8 checker_texture(int cells, uint8_t r0, uint8_t g0, uint8_t b0) {
  render::ImageRgba8 t;
  t.allocate(cells * 8, cells * 8);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const bool on = ((x / 8) + (y / 8)) % 2 == 0;
      uint8_t* p = t.pixel(x, y);
      p[0] = on ? r0 : static_cast<uint8_t>(r0 / 3);
      p[1] = on ? g0 : static_cast<uint8_t>(g0 / 3);
      p[2] = on ? b0 : static_cast<uint8_t>(b0 / 3);
      p[3] = 255;
    }
  return t;
}

void add_quad(render::SyntheticScene& scene, Eigen::Vector3f a, Eigen::Vector3f b,
              Eigen::Vector3f c, Eigen::Vector3f d, render::ImageRgba8 texture) {
  render::TexturedMesh m;
  m.positions_m = {a, b, c, d};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture = std::move(texture);
  scene.meshes.push_back(std::move(m));
}

render::SyntheticScene built_in_scene() {
  render::SyntheticScene s;
  // y is down (camera axes at the identity pose): the floor is at y = +0.6.
  add_quad(s, {-1.6f, -1.0f, 2.5f}, {1.6f, -1.0f, 2.5f}, {1.6f, 0.6f, 2.5f}, {-1.6f, 0.6f, 2.5f},
           checker_texture(8, 200, 180, 120));
  add_quad(s, {-1.6f, 0.6f, 0.8f}, {1.6f, 0.6f, 0.8f}, {1.6f, 0.6f, 2.5f}, {-1.6f, 0.6f, 2.5f},
           checker_texture(6, 90, 140, 200));
  // A box on the floor: its front and top faces.
  add_quad(s, {-0.3f, 0.2f, 1.6f}, {0.2f, 0.2f, 1.6f}, {0.2f, 0.6f, 1.6f}, {-0.3f, 0.6f, 1.6f},
           checker_texture(2, 220, 60, 60));
  add_quad(s, {-0.3f, 0.2f, 2.0f}, {0.2f, 0.2f, 2.0f}, {0.2f, 0.2f, 1.6f}, {-0.3f, 0.2f, 1.6f},
           checker_texture(2, 60, 200, 60));
  s.revision = 1;
  return s;
}

// The mock camera's "video": the scene as that camera sees it (CPU compositor, synthetic only,
// no marks) plus a moving bar, so live video is visibly different from the model.
class SceneCameraRenderer {
 public:
  SceneCameraRenderer(const render::SyntheticScene& scene, core::Pinhole k, core::Pose pose)
      : scene_(scene), k_(k), pose_(pose) {
    image_.allocate(k.width, k.height);
  }
  void operator()(drivers::Frame& f, uint64_t sequence) {
    render::CompositeRequest req;
    req.scene = &scene_;
    req.eye = k_;
    req.T_world_eye = pose_;
    req.marking.style = core::MarkingStyle::kNone;
    req.viewport = {0, 0, k_.width, k_.height};
    compositor_.draw(req, image_);
    const int bar_x = static_cast<int>((sequence * 4) % static_cast<uint64_t>(k_.width));
    for (int y = 0; y < f.height && y < image_.height; ++y) {
      uint8_t* dst =
          f.data.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(f.stride_bytes);
      std::copy(image_.row(y), image_.row(y) + 4 * f.width, dst);
      if (y > f.height * 9 / 10)
        for (int x = bar_x; x < std::min(f.width, bar_x + 12); ++x)
          dst[4 * x] = 255, dst[4 * x + 1] = 255;
    }
  }

 private:
  const render::SyntheticScene& scene_;
  core::Pinhole k_;
  core::Pose pose_;
  render::CpuCompositor compositor_{1};
  render::ImageRgba8 image_;
};

core::Pose yawed(double x_m, double yaw_rad) {
  core::Pose p;
  p.R = Eigen::AngleAxisd(yaw_rad, -Eigen::Vector3d::UnitY()).toRotationMatrix();
  p.t = {x_m, 0.0, 0.0};
  return p;
}

void write_rgba_png(const render::ImageRgba8& img, const std::string& path) {
  cv::Mat rgba(img.height, img.width, CV_8UC4, const_cast<uint8_t*>(img.data.data()),
               static_cast<std::size_t>(img.stride_bytes));
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  const std::string tmp = path + ".tmp.png";
  if (!cv::imwrite(tmp, bgr)) throw std::runtime_error(path + ": cannot write PNG");
  std::filesystem::rename(tmp, path);
}

const char* variant_name(core::Variant v) {
  switch (v) {
    case core::Variant::kVideo:
      return "video";
    case core::Variant::kHybrid:
      return "hybrid";
    case core::Variant::kSynthetic:
      return "synthetic";
  }
  return "?";
}

void write_frames_csv(const std::vector<FrameRow>& rows, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    if (!f) throw std::runtime_error(path + ": cannot open for writing");
    f << "frame,m,w_video,camera,variant,guidance,guidance_distance_m,guidance_dir_x,guidance_dir_"
         "y,"
         "head_x_m,head_y_m,head_z_m\n";
    char buf[256];
    for (const FrameRow& r : rows) {
      std::snprintf(buf, sizeof buf, "%" PRIu64 ",%s,%.4f,%d,%s,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                    r.frame, std::isfinite(r.m) ? std::to_string(r.m).c_str() : "inf", r.w_video,
                    r.camera, variant_name(r.variant), int{r.guidance}, r.guidance_distance_m,
                    r.guidance_dir_x, r.guidance_dir_y, r.head_x_m, r.head_y_m, r.head_z_m);
      f << buf;
    }
    if (!f.flush()) throw std::runtime_error(path + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

// Wraps the station frame: counts allocations after warm-up, saves snapshots outside the count.
class RunWork final : public render::FrameWork {
 public:
  RunWork(render::StationFrame& frame, uint64_t warmup, uint64_t frames, std::string out_dir,
          render::Compositor& compositor, bool windowed)
      : frame_(frame),
        warmup_(warmup),
        frames_(frames),
        out_dir_(std::move(out_dir)),
        compositor_(compositor),
        windowed_(windowed) {}
  void tick(const render::FrameTiming& t) override {
    core::count_allocations_on_this_thread(t.frame >= warmup_);
    frame_.tick(t);
    core::count_allocations_on_this_thread(false);
    if (t.frame == 0 || t.frame == frames_ / 2 || t.frame + 1 == frames_) {
      // Snapshots are for people; the missed deadline they cause on those frames is counted.
      char name[64];
      std::snprintf(name, sizeof name, "/frame_%06" PRIu64 ".png", t.frame);
      write_rgba_png(frame_.image(), out_dir_ + name);
    }
    (void)compositor_;
    (void)windowed_;
  }

 private:
  render::StationFrame& frame_;
  uint64_t warmup_, frames_;
  std::string out_dir_;
  render::Compositor& compositor_;
  bool windowed_;
};

int run(const RunOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec || !fs::is_directory(o.out_dir)) {
    std::fprintf(stderr, "hybrid-station run: --out %s: cannot create directory (%s)\n",
                 o.out_dir.c_str(), ec.message().c_str());
    return 2;
  }

  const render::SyntheticScene scene = built_in_scene();
  // Two calibrated cameras: one at the operator's start pose, one 0.9 m to the right turned
  // 20 deg toward the middle. The head moves from the first toward the second and back.
  const core::Pinhole cam_k{420, 420, 320, 240, 640, 480};
  struct CamSpec {
    std::string id;
    core::Pose pose;
  };
  std::vector<CamSpec> specs = {{"mock-camera-0", yawed(0.0, 0.0)},
                                {"mock-camera-1", yawed(0.9, 20.0 * M_PI / 180.0)}};
  specs.resize(static_cast<std::size_t>(o.cameras));
  std::vector<std::unique_ptr<SceneCameraRenderer>> renderers;
  std::vector<std::unique_ptr<drivers::MockCamera>> cameras;
  std::vector<render::StationCamera> station_cams;
  for (const CamSpec& s : specs) {
    renderers.push_back(std::make_unique<SceneCameraRenderer>(scene, cam_k, s.pose));
    drivers::MockCameraConfig cc;
    cc.id = s.id;
    cc.width = cam_k.width;
    cc.height = cam_k.height;
    cc.rate_hz = 30.0;
    cc.delivery_delay_ns = 8'000'000;
    SceneCameraRenderer* r = renderers.back().get();
    cc.generator = [r](drivers::Frame& f, uint64_t seq) { (*r)(f, seq); };
    cameras.push_back(std::make_unique<drivers::MockCamera>(cc));
    station_cams.push_back({cameras.back().get(), cam_k, s.pose, 1.9});
  }

  const double duration_s = static_cast<double>(o.frames) / o.rate_hz;
  drivers::MockPoseSourceConfig pc;
  pc.rate_hz = 500.0;
  pc.motion = [duration_s](double t_s) {
    // Away from camera 0 toward camera 1 and back, once over the run (raised cosine).
    const double s = 0.5 * (1.0 - std::cos(2.0 * M_PI * std::min(t_s / duration_s, 1.0)));
    drivers::TrajectorySample out;
    out.t_s = t_s;
    out.position_m = {0.9 * s, -0.05 * s, 0.0};
    out.q =
        Eigen::Quaterniond(Eigen::AngleAxisd(20.0 * M_PI / 180.0 * s, -Eigen::Vector3d::UnitY()));
    return out;
  };
  drivers::MockPoseSource pose(pc);

  render::StationFrameConfig cfg;
  const core::Pinhole eye_k{0.9 * o.eye_width,  0.9 * o.eye_width, o.eye_width / 2.0,
                            o.eye_height / 2.0, o.eye_width,       o.eye_height};
  cfg.rig = o.mono ? render::StereoRig::monitor(eye_k) : render::StereoRig{};
  if (!o.mono) cfg.rig.eye = {eye_k, eye_k};
  cfg.workspace.min_m = {-1.2, -0.8, 1.0};
  cfg.workspace.max_m = {1.6, 0.6, 2.5};
  cfg.transition.m_t = o.m_t;
  cfg.transition.eps = o.eps;
  cfg.marking.style = core::MarkingStyle::kFrame;
  cfg.max_rows = o.frames;

  std::unique_ptr<render::PosePredictor> predictor;
  if (o.predictor == "none")
    predictor = std::make_unique<render::HoldPredictor>();
  else if (o.predictor == "cv")
    predictor = std::make_unique<render::ConstantVelocityPredictor>();
  else
    predictor = std::make_unique<render::KalmanPredictor>();

  std::unique_ptr<render::Compositor> compositor;
  std::string compositor_name;
  if (o.gl) {
    render::gl::WindowOptions wo;
    wo.width = cfg.rig.output_width();
    wo.height = cfg.rig.output_height();
    wo.headless = o.headless;
    auto glc = std::make_unique<render::GlCompositor>(wo);
    compositor_name = "OpenGL (" + glc->renderer() + ", " + glc->version() + ")";
    compositor = std::move(glc);
  } else {
    compositor = std::make_unique<render::CpuCompositor>(o.threads);
    compositor_name = "CPU reference (" + std::to_string(o.threads) + " thread(s))";
  }

  std::printf("hybrid-station run\n");
  std::printf("  compositor : %s%s\n", compositor_name.c_str(),
              o.gl && !o.headless ? ", windowed" : ", headless");
  for (const auto& c : cameras)
    std::printf(
        "  camera     : %s (mock, %dx%d RGBA8, 30 Hz, 8 ms delivery delay, renders the scene)\n",
        c->id().c_str(), cam_k.width, cam_k.height);
  std::printf("  head pose  : %s (mock, 500 Hz, scripted: toward camera 1 and back over %.1f s)\n",
              pose.id().c_str(), duration_s);
  std::printf("  predictor  : %s, display = slot start + period + %.1f ms scan-out\n",
              std::string(predictor->name()).c_str(), o.scanout_ms);
  std::printf("  eyes       : %s, %dx%d per eye\n",
              o.mono ? "monitor (1 eye)" : "stereo (IPD 64 mm)", o.eye_width, o.eye_height);
  std::printf("  loop       : %.1f Hz, %" PRIu64 " frames, output %s\n", o.rate_hz, o.frames,
              o.out_dir.c_str());
  std::fflush(stdout);

  render::MonotonicLoopClock clock;
  render::LatencyRecorder latency(o.frames);
  render::StationFrame frame(cfg, station_cams, pose, *predictor, *compositor, &scene, clock,
                             latency);
  render::FrameLoop loop(
      render::FrameLoopConfig{o.rate_hz, static_cast<int64_t>(o.scanout_ms * 1e6), true}, clock);
  RunWork work(frame, o.warmup, o.frames, o.out_dir, *compositor, o.gl && !o.headless);

  for (auto& c : cameras) c->open();
  pose.open();
  for (auto& c : cameras) c->start();
  pose.start();
  for (uint64_t i = 0; i < o.frames; ++i) {
    loop.tick(work);
    if (o.gl && !o.headless && i % 45 == 0) {
      // The HUD line in the window title (outside the counted tick: GLFW may allocate).
      auto* glc = static_cast<render::GlCompositor*>(compositor.get());
      glfwSetWindowTitle(glc->window().handle(), std::string(latency.hud_line()).c_str());
      glc->window().poll_events();
      if (glc->window().should_close()) break;
    }
  }
  pose.stop();
  for (auto& c : cameras) c->stop();

  latency.write_csv(o.out_dir + "/latency.csv");
  latency.write_png(o.out_dir + "/latency.png");
  write_frames_csv(frame.rows(), o.out_dir + "/frames.csv");

  auto line = [](const char* name, const render::LatencyStats& s) {
    std::printf("  %-22s p50 %6.2f  p95 %6.2f  p99 %6.2f  max %6.2f ms  (%zu frames)\n", name,
                s.p50_ms, s.p95_ms, s.p99_ms, s.max_ms, s.count);
  };
  uint64_t counts[3] = {0, 0, 0};
  uint64_t guided = 0;
  for (const FrameRow& r : frame.rows()) {
    ++counts[static_cast<int>(r.variant)];
    guided += r.guidance;
  }
  std::printf("summary\n");
  std::printf("  frames %" PRIu64 ", missed deadlines %" PRIu64 ", skipped slots %" PRIu64 "\n",
              loop.frames(), loop.missed_deadlines(), loop.skipped_slots());
  line("motion-to-photon swap", latency.stats(render::LatencyMetric::kMotionToSwap));
  line("motion-to-photon disp.", latency.stats(render::LatencyMetric::kMotionToDisplay));
  line("video age", latency.stats(render::LatencyMetric::kVideoAge));
  line("render (draw)", latency.stats(render::LatencyMetric::kRender));
  std::printf("  variants: video %" PRIu64 ", hybrid %" PRIu64 ", synthetic %" PRIu64
              " frames; guidance shown %" PRIu64 " frames; camera switches %lu\n",
              counts[0], counts[1], counts[2], guided, frame.selector().switches());
  std::printf("  pose samples accepted %" PRIu64 ", rejected %" PRIu64 "; camera frames fetched:",
              frame.pose_history().accepted(), frame.pose_history().rejected());
  for (uint64_t n : frame.frames_fetched()) std::printf(" %" PRIu64, n);
  std::printf("\n  allocations on the render thread after %" PRIu64 " warm-up frames: %" PRIu64
              "\n",
              o.warmup, core::counted_allocations());
  std::printf("  wrote %s/{latency.csv,latency.png,frames.csv,frame_*.png}\n", o.out_dir.c_str());
  return 0;
}

const CommandRegistrar kRegister{[](CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Run the fixed-rate station loop on the simulated scene (mock cameras + scripted head "
      "motion).\n"
      "Example:\n  hybrid-station run --headless --frames 900 --rate 90 --out /tmp/run1\n"
      "Writes DIR/latency.csv, DIR/latency.png, DIR/frames.csv (m, w_video, camera, variant per\n"
      "frame) and three snapshots DIR/frame_*.png, then prints a summary.");
  cmd->add_flag("--headless", opts->headless, "No window (the CPU compositor never opens one)");
  cmd->add_flag("--gl", opts->gl,
                "OpenGL compositor (needs a display; with --headless an invisible window)");
  cmd->add_option("--frames", opts->frames, "Frames to run")
      ->check(CLI::Range(uint64_t{1}, uint64_t{10'000'000}));
  cmd->add_option("--rate", opts->rate_hz, "Target rate in Hz (60, 72, 90 ...)")
      ->check(CLI::Range(1.0, 1000.0));
  cmd->add_option("--out", opts->out_dir, "Output directory (created)")->required();
  cmd->add_flag("--mono", opts->mono, "One eye (a monitor) instead of a stereo HMD");
  cmd->add_option("--eye-width", opts->eye_width, "Eye image width")->check(CLI::Range(16, 4096));
  cmd->add_option("--eye-height", opts->eye_height, "Eye image height")
      ->check(CLI::Range(16, 4096));
  cmd->add_option("--predictor", opts->predictor, "none | cv | kalman")
      ->check(CLI::IsMember({"none", "cv", "kalman"}));
  cmd->add_option("--scanout-ms", opts->scanout_ms, "Vsync to photons")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--threads", opts->threads, "CPU compositor threads (1 or 2)")
      ->check(CLI::Range(1, 2));
  cmd->add_option("--cameras", opts->cameras, "Mock cameras (1 or 2)")->check(CLI::Range(1, 2));
  cmd->add_option("--m-t", opts->m_t, "Transition threshold m_t (px)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--eps", opts->eps, "Transition half band eps (px)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--warmup", opts->warmup, "Frames before allocations are counted");
  cmd->callback([opts, &exit_code] {
    try {
      exit_code = run(*opts);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hybrid-station run: %s\n", e.what());
      exit_code = 1;
    }
  });
}};

}  // namespace
}  // namespace hd::station
