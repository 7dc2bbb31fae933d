// hybrid-bench-render: the compositors' accuracy against time, printed as one table in one run.
//
//   nearest vs bilinear video sampling: error against an exact (supersampled analytic) render;
//   OpenCV's cv::warpPerspective of the same frame, 1 thread and default threads;
//   CPU compositor video warp and full hybrid frame, 1 and 2 threads, plane and model-depth video
//   views (core/video_view.h);
//   GL compositor (needs a display: run under xvfb-run for llvmpipe): full frame, region vs full
//   upload (bytes, time).

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "core/view_measure.h"
#include "core/view_setup.h"
#include "render/compositor/cpu_compositor.h"
#include "render/compositor/demo_scene.h"
#include "render/compositor/look_pose.h"
#include "render/compositor/video_warp.h"
#include "render/gl/gl_compositor.h"

namespace {

using hd::core::Pinhole;
using hd::core::Pose;
using hd::render::CompositeRequest;
using hd::render::ImageRgba8;

Pinhole pinhole(double f, int w, int h) {
  return Pinhole::centred(f, w, h);
}

// The procedural pattern on the plane, in real-image pixel coordinates: detail from 5 to 40 px.
double pattern(double u, double v) {
  return 127.5 + 50.0 * std::sin(u * 0.16 + 0.3 * v * 0.05) * std::cos(v * 0.11) +
         40.0 * std::sin((u + v) * 0.45) + 25.0 * std::cos((u - 2 * v) * 0.9);
}

// Seconds of CPU time used by the whole process (all threads) so far.
double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Timing {
  double wall_ms = 0.0;  ///< median wall time of one run
  double min_ms = 0.0;   ///< fastest run
  double cpu_ms = 0.0;   ///< median process CPU time of one run (all threads; load-insensitive)
};

// Median (and minimum) wall time of `fn` in milliseconds, and its median CPU time: on a loaded
// machine the wall time includes waiting for a core, the CPU time does not.
Timing time_ms(int runs, const std::function<void()>& fn) {
  fn();  // warm-up
  std::vector<double> t, c;
  for (int i = 0; i < runs; ++i) {
    const double c0 = process_cpu_s();
    const auto a = std::chrono::steady_clock::now();
    fn();
    const auto b = std::chrono::steady_clock::now();
    c.push_back(1e3 * (process_cpu_s() - c0));
    t.push_back(std::chrono::duration<double, std::milli>(b - a).count());
  }
  Timing r;
  r.min_ms = *std::min_element(t.begin(), t.end());
  std::nth_element(t.begin(), t.begin() + runs / 2, t.end());
  std::nth_element(c.begin(), c.begin() + runs / 2, c.end());
  r.wall_ms = t[runs / 2];
  r.cpu_ms = c[runs / 2];
  return r;
}

struct Row {
  std::string what;
  std::string error;
  Timing time;
  std::string bytes;
  std::string note;
};

std::string fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-render: time per frame of the CPU compositor's stages (video warp, synthetic "
      "view, blend) at 1 and 2 threads, beside OpenCV's warpPerspective, with the error of each"};
  int runs = 30;
  app.add_option("runs", runs, "timed runs of each row; the median is reported (at least 3)")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  runs = std::max(3, runs);
  double load_before[3] = {0, 0, 0};
  if (getloadavg(load_before, 3) != 3) load_before[0] = load_before[1] = load_before[2] = -1;
  const Pinhole real = pinhole(1400.0, 1600, 1200);
  const Pinhole eye = pinhole(700.0, 800, 600);
  const Pose T_wr = hd::render::look_pose(0.0, -5.0, {0.0, -0.1, -0.2});
  const Pose T_we = hd::render::look_pose(5.0, -3.0, {0.06, -0.03, 0.05});
  const double d_m = 1.3;
  std::vector<Row> rows;

  // --- Video frame of the analytic pattern: each pixel the 4x4 box average over its area. ---
  hd::drivers::Frame pattern_frame;
  pattern_frame.allocate_rgba(real.width, real.height);
  for (int y = 0; y < real.height; ++y) {
    for (int x = 0; x < real.width; ++x) {
      double s = 0;
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) s += pattern(x + (i + 0.5) / 4, y + (j + 0.5) / 4);
      uint8_t* p = pattern_frame.data.data() + y * pattern_frame.stride_bytes + 4 * x;
      p[0] = p[1] = p[2] = static_cast<uint8_t>(std::clamp(s / 16.0 + 0.5, 0.0, 255.0));
      p[3] = 255;
    }
  }
  // --- Exact render: the eye pixel's 4x4 supersampled average of the pattern via the plane. ---
  const hd::render::VideoWarp warp = hd::render::VideoWarp::make(eye, T_we, real, T_wr, d_m);
  std::vector<double> exact(static_cast<std::size_t>(eye.width) * eye.height, -1.0);
  for (int y = 0; y < eye.height; ++y) {
    for (int x = 0; x < eye.width; ++x) {
      double s = 0;
      bool inside = true;
      for (int j = 0; j < 4 && inside; ++j) {
        for (int i = 0; i < 4; ++i) {
          const Eigen::Vector3d h =
              warp.H * Eigen::Vector3d(x + (i + 0.5) / 4, y + (j + 0.5) / 4, 1);
          const double u = h.x() / h.z(), v = h.y() / h.z();
          if (h.z() <= 0 || u < 2 || v < 2 || u > real.width - 2 || v > real.height - 2) {
            inside = false;
            break;
          }
          s += pattern(u, v);
        }
      }
      if (inside) exact[static_cast<std::size_t>(y) * eye.width + x] = s / 16.0;
    }
  }
  auto rms_vs_exact = [&](const ImageRgba8& img) {
    double se = 0;
    long n = 0;
    for (int y = 0; y < eye.height; ++y) {
      for (int x = 0; x < eye.width; ++x) {
        const double e = exact[static_cast<std::size_t>(y) * eye.width + x];
        if (e < 0) continue;
        const double d = img.pixel(x, y)[0] - e;
        se += d * d;
        ++n;
      }
    }
    return n ? std::sqrt(se / n) : -1.0;
  };

  CompositeRequest video_req;
  video_req.eye = eye;
  video_req.T_world_eye = T_we;
  video_req.video = &pattern_frame;
  video_req.real = real;
  video_req.T_world_real = T_wr;
  video_req.d_m = d_m;
  video_req.has_region = true;
  video_req.region = {0, 0, double(real.width), double(real.height)};
  video_req.transition = {hd::core::Variant::kVideo, 1.0, 0.0};
  video_req.mode = hd::core::TransitionMode::kAbrupt;
  video_req.marking.style = hd::core::MarkingStyle::kNone;
  video_req.viewport = {0, 0, eye.width, eye.height};
  ImageRgba8 out;
  out.allocate(eye.width, eye.height);

  for (int threads : {1, 2}) {
    for (auto sampling :
         {hd::render::VideoSampling::kNearest, hd::render::VideoSampling::kBilinear}) {
      hd::render::CpuCompositor cpu(threads);
      CompositeRequest r = video_req;
      r.sampling = sampling;
      const Timing ms = time_ms(runs, [&] { cpu.draw(r, out); });
      rows.push_back(
          {std::string("CPU video warp, ") +
               (sampling == hd::render::VideoSampling::kNearest ? "nearest" : "bilinear") + ", " +
               std::to_string(threads) + " thread" + (threads > 1 ? "s" : ""),
           fmt("%.2f", rms_vs_exact(out)), ms, "-", "1600x1200 -> 800x600"});
    }
  }

  // --- OpenCV's warpPerspective of the same frame (its pixel centres are at integers). ---
  {
    cv::Mat src(real.height, real.width, CV_8UC4, pattern_frame.data.data(),
                pattern_frame.stride_bytes);
    cv::Mat dst(eye.height, eye.width, CV_8UC4, out.data.data(), out.stride_bytes);
    Eigen::Matrix3d shift_in = Eigen::Matrix3d::Identity(), shift_out = Eigen::Matrix3d::Identity();
    shift_in(0, 2) = shift_in(1, 2) = 0.5;     // OpenCV dst pixel -> our continuous coordinate
    shift_out(0, 2) = shift_out(1, 2) = -0.5;  // our continuous source coordinate -> OpenCV's
    const Eigen::Matrix3d M = shift_out * warp.H * shift_in;
    cv::Mat Mcv(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Mcv.at<double>(i, j) = M(i, j);
    const int default_threads = cv::getNumThreads();
    for (int threads : {1, default_threads}) {
      cv::setNumThreads(threads);
      const Timing ms = time_ms(runs, [&] {
        cv::warpPerspective(src, dst, Mcv, dst.size(), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                            cv::BORDER_CONSTANT);
      });
      rows.push_back({"OpenCV warpPerspective bilinear, " +
                          (threads == 1 ? std::string("1 thread")
                                        : "default (" + std::to_string(threads) + ") threads"),
                      fmt("%.2f", rms_vs_exact(out)), ms, "-", "same frame and homography"});
    }
    cv::setNumThreads(default_threads);
  }

  // --- A full hybrid frame: the demo model, its video, per-pixel blend, desaturation. ---
  const hd::render::SyntheticScene scene = hd::render::make_demo_scene();
  hd::drivers::Frame demo_frame;
  hd::render::render_demo_frame(scene, real, T_wr, 25, demo_frame);
  CompositeRequest hybrid = video_req;
  hybrid.scene = &scene;
  hybrid.video = &demo_frame;
  hybrid.T_world_eye = hd::render::look_pose(12.0, -5.0, {0.2, -0.05, 0.1});
  hybrid.mode = hd::core::TransitionMode::kPerPixel;
  hybrid.transition = {hd::core::Variant::kHybrid, 0.7, 0.3};
  hybrid.marking.style = hd::core::MarkingStyle::kDesaturate;
  ImageRgba8 cpu_hybrid;
  cpu_hybrid.allocate(eye.width, eye.height);
  // The video views side by side: plane (also fitted-plane's cost here: its d is the station's),
  // model-depth with its camera depth map reused (the model and camera unchanged, as between
  // model updates), and with the map re-drawn every frame (a model update every frame).
  CompositeRequest model_depth = hybrid;
  model_depth.video_view = hd::core::VideoView::kModelDepth;
  hd::render::SyntheticScene changing = scene;
  CompositeRequest redrawn = model_depth;
  redrawn.scene = &changing;
  for (int threads : {1, 2}) {
    const std::string t = std::to_string(threads) + " thread" + (threads > 1 ? "s" : "");
    hd::render::CpuCompositor cpu(threads);
    const Timing ms = time_ms(runs, [&] { cpu.draw(hybrid, cpu_hybrid); });
    rows.push_back({"CPU full hybrid frame, plane view, " + t, "reference", ms, "-",
                    "800x600, target 11.1 ms"});
    hd::render::CpuCompositor cpu_depth(threads);
    const Timing md = time_ms(runs, [&] { cpu_depth.draw(model_depth, cpu_hybrid); });
    rows.push_back({"CPU full hybrid frame, model-depth view, " + t, "-", md, "-",
                    fmt("%.2f x the plane's CPU ms", md.cpu_ms / ms.cpu_ms)});
    const Timing mr = time_ms(runs, [&] {
      ++changing.revision;
      cpu_depth.draw(redrawn, cpu_hybrid);
    });
    rows.push_back({"  same, camera depth map re-drawn each frame", "-", mr, "-",
                    fmt("%.2f x; 1600x1200 map", mr.cpu_ms / ms.cpu_ms)});
  }

  {
    hd::render::CpuCompositor reference;  // the GL rows compare with the plane view's picture
    reference.draw(hybrid, cpu_hybrid);
  }

  // --- GL (llvmpipe under xvfb-run when there is no GPU). ---
  std::string gl_note;
  try {
    hd::render::gl::WindowOptions o;
    o.headless = true;
    o.vsync = false;
    hd::render::GlCompositor gl(o);
    gl_note = gl.renderer();
    ImageRgba8 gl_out;
    gl_out.allocate(eye.width, eye.height);
    uint64_t seq = 0;
    // Every draw gets a new frame sequence so the video is uploaded every time.
    auto timed_draw = [&](CompositeRequest r) {
      return time_ms(runs, [&] {
        demo_frame.sequence = ++seq;
        gl.draw(r, gl_out);
      });
    };
    const Timing ms = timed_draw(hybrid);
    double se = 0;
    for (std::size_t i = 0; i < gl_out.data.size(); ++i) {
      if (i % 4 == 3) continue;
      const double d = double(gl_out.data[i]) - double(cpu_hybrid.data[i]);
      se += d * d;
    }
    const double mse = se / (3.0 * eye.width * eye.height);
    rows.push_back({"GL full hybrid frame + readback",
                    fmt("PSNR %.1f dB vs CPU", 10 * std::log10(65025.0 / std::max(mse, 1e-12))), ms,
                    "-", gl_note});
    const Timing gd = timed_draw(model_depth);
    rows.push_back({"GL full hybrid frame, model-depth view", "-", gd, "-",
                    fmt("%.2f x the plane's wall ms", gd.wall_ms / ms.wall_ms)});
    // Region vs full upload: a narrow eye sees part of the frame; region from core's measure.
    CompositeRequest narrow = hybrid;
    narrow.eye = pinhole(1400.0, 800, 600);
    hd::core::ViewSetup s;
    s.real = real;
    s.T_world_real = T_wr;
    s.virt = narrow.eye;
    s.T_world_virt = narrow.T_world_eye;
    s.d_m = d_m;
    s.near_m = narrow.near_m;
    s.workspace.min_m = {-1.5, -1.0, 0.0};
    s.workspace.max_m = {1.5, 0.5, 2.5};
    const hd::core::ViewMeasure m = hd::core::measure_view(s);
    if (m.has_region) {
      for (bool region : {false, true}) {
        CompositeRequest r = narrow;
        r.region = region ? m.region : hd::core::PixelRect{0, 0, 1600, 1200};
        const uint64_t b0 = gl.stats().video_bytes_uploaded, n0 = gl.stats().video_uploads;
        const Timing t = timed_draw(r);
        const double per = double(gl.stats().video_bytes_uploaded - b0) /
                           double(std::max<uint64_t>(1, gl.stats().video_uploads - n0));
        rows.push_back(
            {std::string("GL frame, narrow eye, ") + (region ? "region" : "full") + " upload", "-",
             t, fmt("%.0f", per),
             region ? "glTexSubImage2D of the update region" : "whole 1600x1200 frame"});
      }
    }
  } catch (const std::exception& e) {
    rows.push_back({"GL rows", "-", Timing{}, "-",
                    std::string("skipped: ") + e.what() + " (run under xvfb-run)"});
  }

  double load_after[3] = {0, 0, 0};
  if (getloadavg(load_after, 3) != 3) load_after[0] = load_after[1] = load_after[2] = -1;
  std::printf(
      "hybrid-bench-render: median of %d runs; error = RMS (8-bit levels) vs the exact\n"
      "supersampled render of an analytic pattern, over pixels whose footprint is inside the "
      "frame\nload average (1, 5, 15 min): %.2f %.2f %.2f before, %.2f %.2f %.2f after; CPU ms = "
      "process CPU time of one run, all threads\n\n",
      runs, load_before[0], load_before[1], load_before[2], load_after[0], load_after[1],
      load_after[2]);
  std::printf("| %-46s | %-20s | %9s | %7s | %7s | %10s | %s |\n", "case", "error", "median ms",
              "min ms", "CPU ms", "bytes/frame", "note");
  std::printf("|%s|%s|%s|%s|%s|%s|%s|\n", std::string(48, '-').c_str(),
              std::string(22, '-').c_str(), std::string(11, '-').c_str(),
              std::string(9, '-').c_str(), std::string(9, '-').c_str(),
              std::string(12, '-').c_str(), "------");
  for (const Row& r : rows) {
    std::printf("| %-46s | %-20s | %9.2f | %7.2f | %7.2f | %10s | %s |\n", r.what.c_str(),
                r.error.c_str(), r.time.wall_ms, r.time.min_ms, r.time.cpu_ms, r.bytes.c_str(),
                r.note.c_str());
  }
  return 0;
}
