// hybrid-bench-lens: what pre-distortion costs per frame beside the geometric error it leaves,
// measured against the exact per-pixel lens model, in one run.
//
//   CPU: sample points evaluated from the radius in AVX2 floats (the default; 1 and 2 threads,
//        and the scalar rows), the first version's table of green positions (1 and 2 threads) and
//        evaluating the polynomial per pixel and channel in double precision (the reference);
//        peers: OpenCV cv::remap with the same sample points (one map per channel, 3 passes) and
//        with the green map only (no chromatic correction).
//   GL (needs a display: xvfb-run for llvmpipe): the distortion mesh at several resolutions.
//
// The case is two 800x600 eye halves of a panel (1600x600) behind the OSVR HDK 1.3's lens
// polynomial with the DK1's chromatic aberration, so every channel has its own sample points.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "render/gl/gl_compositor.h"
#include "render/lens/cpu_predistorter.h"
#include "render/lens/hmd_profile_file.h"
#include "render/lens/lens_warp.h"

namespace {

using hd::render::ImageRgba8;
using namespace hd::render::lens;

double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Timing {
  double wall_ms = 0, min_ms = 0, cpu_ms = 0;
};

// Median and fastest wall time and median process CPU time of `fn` over `runs` runs.
Timing time_it(int runs, const std::function<void()>& fn) {
  fn();  // warm caches and lazily built state
  std::vector<double> wall, cpu;
  for (int i = 0; i < runs; ++i) {
    const double c0 = process_cpu_s();
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    const auto t1 = std::chrono::steady_clock::now();
    cpu.push_back(1e3 * (process_cpu_s() - c0));
    wall.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], wall.front(), cpu[cpu.size() / 2]};
}

// /proc/loadavg's line: the figures of a shared machine mean little without it.
std::string load_average() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  char line[128] = "?\n";
  if (f) {
    if (!std::fgets(line, sizeof line, f)) std::snprintf(line, sizeof line, "?\n");
    std::fclose(f);
  }
  return line;
}

HmdProfile bench_profile() {
  HmdProfile p;
  p.name = "bench";
  p.neutral = false;
  p.panel_width_px = 1600;
  p.panel_height_px = 600;
  p.panel_width_m = 1600 * 6.3417e-5;
  p.panel_height_m = 600 * 6.3417e-5;
  p.lens_centre_m = {Eigen::Vector2d(p.eye_panel_width_m() / 2, p.panel_height_m / 2),
                     Eigen::Vector2d(p.eye_panel_width_m() / 2, p.panel_height_m / 2)};
  p.coefficients = {0, 1, -1.74, 5.15, -1.27, -2.23};
  p.r_unit_m = {p.eye_panel_width_m(), p.panel_height_m};
  p.aberration = {0.985, 1.0, 1.015};
  p.fov_deg = Eigen::Vector2d(90.0, 70.0);
  return p;
}

ImageRgba8 eyes_pattern(const LensWarp& w) {
  ImageRgba8 img;
  img.allocate(2 * w.eye_width(), w.eye_height());
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      uint8_t* p = img.pixel(x, y);
      for (int c = 0; c < 3; ++c)
        p[c] = static_cast<uint8_t>(127.5 + 60 * std::sin(x * 0.13 + c) * std::cos(y * 0.09) +
                                    60 * std::sin((x + 2 * y) * 0.31 + c));
      p[3] = 255;
    }
  return img;
}

double rms_levels(const ImageRgba8& a, const ImageRgba8& b) {
  double s = 0;
  std::size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = double(a.pixel(x, y)[c]) - double(b.pixel(x, y)[c]);
        s += d * d;
        ++n;
      }
  return std::sqrt(s / static_cast<double>(n));
}

// Per-channel remap maps in the eyes' picture, and the largest difference of the float table's
// sample points from the double-precision model (the table's geometric error).
struct Maps {
  std::array<cv::Mat, 3> map;  // CV_32FC2, pixel-centre convention shifted to OpenCV's
  double table_error_px = 0;
  double green_only_error_px = 0;  // ignoring aberration: R and B sampled at green's point
};

Maps make_maps(const LensWarp& w) {
  Maps m;
  for (auto& mm : m.map) mm.create(w.panel_height(), w.panel_width(), CV_32FC2);
  const int hw = w.eye_panel_width();
  for (int y = 0; y < w.panel_height(); ++y)
    for (int x = 0; x < w.panel_width(); ++x) {
      const int e = x < hw ? 0 : 1;
      double ug = 0, vg = 0;
      const bool in = w.source(e, x - e * hw + 0.5, y + 0.5, 1, &ug, &vg);
      for (int c = 0; c < 3; ++c) {
        double u = -10, v = -10;
        if (in) w.source(e, x - e * hw + 0.5, y + 0.5, c, &u, &v);
        const float fu = static_cast<float>(u - w.eye(e).cx),
                    fv = static_cast<float>(v - w.eye(e).cy);
        // The table's own arithmetic: green offset (float) scaled per channel about the centre.
        const double sc = w.channel_scale(c);
        const float tu = static_cast<float>(w.eye(e).cx + e * w.eye_width()) +
                         static_cast<float>(sc) * static_cast<float>(ug - w.eye(e).cx);
        const float tv = static_cast<float>(w.eye(e).cy) +
                         static_cast<float>(sc) * static_cast<float>(vg - w.eye(e).cy);
        if (in) {
          m.table_error_px =
              std::max(m.table_error_px, std::hypot(tu - (u + e * w.eye_width()), tv - v));
          m.green_only_error_px = std::max(m.green_only_error_px, std::hypot(u - ug, v - vg));
        }
        (void)fu, (void)fv;
        m.map[static_cast<std::size_t>(c)].at<cv::Vec2f>(y, x) =
            cv::Vec2f(static_cast<float>(u + e * w.eye_width() - 0.5), static_cast<float>(v - 0.5));
      }
    }
  return m;
}

// Largest distance of a predistorter's sample points (before the 1/256 px grid every CPU path,
// the exact one included, samples on) from the double-precision model, over all usable pixels
// and channels.
double sample_error_px(const CpuPredistorter& pd) {
  const LensWarp& w = pd.warp();
  double worst = 0;
  for (int e = 0; e < 2; ++e)
    for (int y = 0; y < w.panel_height(); ++y)
      for (int x = 0; x < w.eye_panel_width(); ++x)
        for (int c = 0; c < 3; ++c) {
          double u = 0, v = 0, pu = 0, pv = 0;
          if (!w.source(e, x + 0.5, y + 0.5, c, &u, &v)) break;
          pd.sample_point(e, x, y, c, &pu, &pv);
          worst = std::max(worst, std::hypot(pu - u, pv - v));
        }
  return worst;
}

// Largest distance between a mesh's linearly interpolated green sample point (vertices every
// `step` px, two triangles per cell as GlCompositor::set_lens builds them) and the exact one,
// over eye 0's usable pixels.
double mesh_error_px(const LensWarp& w, int step) {
  double worst = 0;
  for (int y = 0; y < w.panel_height(); ++y)
    for (int x = 0; x < w.eye_panel_width(); ++x) {
      double u = 0, v = 0;
      if (!w.source(0, x + 0.5, y + 0.5, 1, &u, &v)) continue;
      const int x0 = x / step * step, y0 = y / step * step;
      const int x1 = std::min(x0 + step, w.eye_panel_width()),
                y1 = std::min(y0 + step, w.panel_height());
      const double fx = (x + 0.5 - x0) / (x1 - x0), fy = (y + 0.5 - y0) / (y1 - y0);
      double a[2], b[2], c[2], d[2];
      w.source_unclamped(0, x0, y0, 1, &a[0], &a[1]);
      w.source_unclamped(0, x1, y0, 1, &b[0], &b[1]);
      w.source_unclamped(0, x0, y1, 1, &c[0], &c[1]);
      w.source_unclamped(0, x1, y1, 1, &d[0], &d[1]);
      double iu = 0, iv = 0;
      if (fx + fy <= 1) {
        iu = a[0] + fx * (b[0] - a[0]) + fy * (c[0] - a[0]);
        iv = a[1] + fx * (b[1] - a[1]) + fy * (c[1] - a[1]);
      } else {
        iu = d[0] + (1 - fx) * (c[0] - d[0]) + (1 - fy) * (b[0] - d[0]);
        iv = d[1] + (1 - fx) * (c[1] - d[1]) + (1 - fy) * (b[1] - d[1]);
      }
      worst = std::max(worst, std::hypot(iu - u, iv - v));
    }
  return worst;
}

// docs/hmd_grid.png: a straight grid in both eye images (left) and the DK1 panel it becomes
// (right), R, G and B pre-distorted separately (the colour fringes toward the rim).
void write_figure(const std::string& path) {
  const LensWarp w(load_hmd_profile(shipped_profile_dir() + "/oculus-dk1.yaml"));
  ImageRgba8 eyes;
  eyes.allocate(2 * w.eye_width(), w.eye_height());
  for (int y = 0; y < eyes.height; ++y)
    for (int x = 0; x < eyes.width; ++x) {
      const int e = x < w.eye_width() ? 0 : 1;
      const double u = x - e * w.eye_width() + 0.5 - w.eye(e).cx, v = y + 0.5 - w.eye(e).cy;
      const bool line =
          std::abs(std::remainder(u, 60.0)) < 2.0 || std::abs(std::remainder(v, 60.0)) < 2.0;
      uint8_t* p = eyes.pixel(x, y);
      p[0] = p[1] = p[2] = line ? 255 : 40;
      p[3] = 255;
    }
  ImageRgba8 panel;
  panel.allocate(w.panel_width(), w.panel_height());
  CpuPredistorter(w, 1).apply(eyes, panel);
  const cv::Mat e(eyes.height, eyes.width, CV_8UC4, eyes.data.data());
  const cv::Mat p(panel.height, panel.width, CV_8UC4, panel.data.data());
  cv::Mat e_small, both, bgr;
  cv::resize(e, e_small, cv::Size(eyes.width * panel.height / eyes.height, panel.height), 0, 0,
             cv::INTER_AREA);
  cv::Mat gap(panel.height, 24, CV_8UC4, cv::Scalar(255, 255, 255, 255));
  cv::hconcat(std::vector<cv::Mat>{e_small, gap, p}, both);
  cv::cvtColor(both, bgr, cv::COLOR_RGBA2BGR);
  cv::imwrite(path, bgr);
  std::printf("wrote %s (eyes %dx%d scaled to the panel's height | DK1 panel %dx%d)\n",
              path.c_str(), eyes.width, eyes.height, panel.width, panel.height);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-lens: cost per frame of the HMD lens pre-distortion beside the geometric error "
      "it leaves, against the exact lens model and OpenCV's cv::remap, in one run"};
  int runs = 21;
  std::string figure;
  app.add_option("runs", runs, "timed runs of each method; the median is reported (at least 3)")
      ->check(CLI::PositiveNumber);
  app.add_option("--figure", figure, "write the distortion figure (PNG) to this file and stop");
  app.footer("The GL rows need a display: run under xvfb-run for llvmpipe.");
  CLI11_PARSE(app, argc, argv);
  if (!figure.empty()) {
    write_figure(figure.c_str());
    return 0;
  }
  runs = std::max(3, runs);
  const LensWarp warp(bench_profile());
  const ImageRgba8 eyes = eyes_pattern(warp);
  std::printf("load average at the start: %s", load_average().c_str());
  std::printf(
      "hybrid-bench-lens: panel %dx%d (two 800x600 eye halves), eye images %dx%d, %d runs\n",
      warp.panel_width(), warp.panel_height(), warp.eye_width(), warp.eye_height(), runs);

  using Method = CpuPredistorter::Method;
  ImageRgba8 exact, radial1, radial2, avx2_1, avx2_2, scalar1, table1, table2;
  for (ImageRgba8* i : {&exact, &radial1, &radial2, &avx2_1, &avx2_2, &scalar1, &table1, &table2})
    i->allocate(warp.panel_width(), warp.panel_height());
  using Simd = CpuPredistorter::Simd;
  CpuPredistorter pd1(warp, 1), pd2(warp, 2), pd_scalar(warp, 1, Simd::kNone);
  CpuPredistorter av1(warp, 1, Simd::kAvx2), av2(warp, 2, Simd::kAvx2);
  CpuPredistorter tb1(warp, 1, Simd::kBest, Method::kPositionTable),
      tb2(warp, 2, Simd::kBest, Method::kPositionTable);
  const Maps maps = make_maps(warp);

  // Interleaved rounds, so that a burst of load elsewhere on the machine hits every variant.
  const int rounds = 3;
  std::vector<Timing> tr1, tr2, ta1, ta2, ttb1, ttb2;
  for (int k = 0; k < rounds; ++k) {
    tr1.push_back(time_it(runs, [&] { pd1.apply(eyes, radial1); }));
    tr2.push_back(time_it(runs, [&] { pd2.apply(eyes, radial2); }));
    ta1.push_back(time_it(runs, [&] { av1.apply(eyes, avx2_1); }));
    ta2.push_back(time_it(runs, [&] { av2.apply(eyes, avx2_2); }));
    ttb1.push_back(time_it(runs, [&] { tb1.apply(eyes, table1); }));
    ttb2.push_back(time_it(runs, [&] { tb2.apply(eyes, table2); }));
  }
  auto best = [](const std::vector<Timing>& v) {
    return *std::min_element(
        v.begin(), v.end(), [](const Timing& a, const Timing& b) { return a.wall_ms < b.wall_ms; });
  };
  const Timing t1 = best(tr1), t2 = best(tr2), tt1 = best(ttb1), tt2 = best(ttb2);
  const Timing ta_1 = best(ta1), ta_2 = best(ta2);
  const Timing t_scalar = time_it(runs, [&] { pd_scalar.apply(eyes, scalar1); });
  const Timing t_exact = time_it(std::max(3, runs / 4), [&] { pd1.apply_exact(eyes, exact); });

  cv::setNumThreads(1);
  const cv::Mat src(eyes.height, eyes.width, CV_8UC4, const_cast<uint8_t*>(eyes.data.data()),
                    static_cast<std::size_t>(eyes.stride_bytes));
  cv::Mat out3(warp.panel_height(), warp.panel_width(), CV_8UC4), tmp;
  const Timing t_cv3 = time_it(runs, [&] {
    std::array<cv::Mat, 3> ch;
    for (int c = 0; c < 3; ++c) cv::remap(src, ch[c], maps.map[c], cv::noArray(), cv::INTER_LINEAR);
    for (int c = 0; c < 3; ++c)
      cv::mixChannels(&ch[c], 1, &out3, 1, std::array<int, 2>{c, c}.data(), 1);
  });
  const Timing t_cv1 =
      time_it(runs, [&] { cv::remap(src, tmp, maps.map[1], cv::noArray(), cv::INTER_LINEAR); });
  ImageRgba8 cv_img;
  cv_img.allocate(warp.panel_width(), warp.panel_height());
  for (int y = 0; y < cv_img.height; ++y)
    std::memcpy(cv_img.row(y), out3.ptr(y), static_cast<std::size_t>(4 * cv_img.width));

  const double radial_err = sample_error_px(pd1), table_err = sample_error_px(tb1);
  std::printf(
      "\n| CPU pre-distortion, 1600x600 panel | max geometric error px | RMS levels vs exact | "
      "median ms | min ms | CPU ms |\n|---|---|---|---|---|---|\n");
  auto row = [](const char* name, double geo, double rms, const Timing& t) {
    std::printf("| %s | %.2g | %.3f | %.3f | %.3f | %.3f |\n", name, geo, rms, t.wall_ms, t.min_ms,
                t.cpu_ms);
  };
  row("exact per-pixel polynomial, double, 1 thread (reference)", 0.0, 0.0, t_exact);
  const char* kernel = pd1.simd() == Simd::kAvx512 ? "AVX-512"
                       : pd1.simd() == Simd::kAvx2 ? "AVX2"
                                                   : "scalar";
  char name[128];
  std::snprintf(name, sizeof name, "**points from the radius (%s), 1 thread**", kernel);
  row(name, radial_err, rms_levels(radial1, exact), t1);
  std::snprintf(name, sizeof name, "**points from the radius (%s), 2 threads**", kernel);
  row(name, radial_err, rms_levels(radial2, exact), t2);
  if (pd1.simd() == Simd::kAvx512) {
    row("points from the radius, AVX2 rows, 1 thread", radial_err, rms_levels(avx2_1, exact), ta_1);
    row("points from the radius, AVX2 rows, 2 threads", radial_err, rms_levels(avx2_2, exact),
        ta_2);
  }
  row("points from the radius, scalar rows, 1 thread", radial_err, rms_levels(scalar1, exact),
      t_scalar);
  row("previous: table of green positions (AVX2), 1 thread", table_err, rms_levels(table1, exact),
      tt1);
  row("previous: table of green positions (AVX2), 2 threads", table_err, rms_levels(table2, exact),
      tt2);
  row("peer: OpenCV remap per channel (3 maps), 1 thread", maps.table_error_px,
      rms_levels(cv_img, exact), t_cv3);
  row("peer: OpenCV remap, green map for all channels, 1 thread", maps.green_only_error_px,
      std::nan(""), t_cv1);
  std::printf(
      "\nmedian wall of the best of %d interleaved rounds\nradius / previous table: %.3f (1 "
      "thread), %.3f (2 threads); radius / OpenCV 3-map "
      "remap: %.3f; radius / green-only remap: %.3f\n",
      rounds, t1.wall_ms / tt1.wall_ms, t2.wall_ms / tt2.wall_ms, t1.wall_ms / t_cv3.wall_ms,
      t1.wall_ms / t_cv1.wall_ms);
  std::printf("2 threads: %s the issue's 1.5 ms (median %.3f ms); load average %s",
              t2.wall_ms <= 1.5 ? "within" : "over", t2.wall_ms, load_average().c_str());

  // GL: the fragment pass and meshes of several resolutions (pass + read-back, llvmpipe).
  std::unique_ptr<hd::render::GlCompositor> gl;
  try {
    hd::render::gl::WindowOptions o;
    o.headless = true;
    gl = std::make_unique<hd::render::GlCompositor>(o);
  } catch (const std::exception& e) {
    std::printf("\nGL: skipped (%s; run under xvfb-run)\n", e.what());
    return 0;
  }
  std::printf(
      "\n| GL pre-distortion (%s), pass + read-back | max geometric error px | RMS levels "
      "vs CPU exact | median ms | min ms | CPU ms |\n|---|---|---|---|---|---|\n",
      gl->renderer().c_str());
  ImageRgba8 gl_panel;
  gl_panel.allocate(warp.panel_width(), warp.panel_height());
  for (int step : {0, 2, 4, 8, 16, 32}) {
    gl->set_lens_mesh_step(step);
    gl->set_lens(&warp);
    gl->load_picture(eyes);
    const Timing t = time_it(runs, [&] { gl->predistort(eyes, gl_panel); });
    char name[64];
    if (step == 0)
      std::snprintf(name, sizeof name, "**exact fragment pass (default)**");
    else
      std::snprintf(name, sizeof name, "mesh, a vertex every %d px", step);
    row(name, step == 0 ? 0.0 : mesh_error_px(warp, step), rms_levels(gl_panel, exact), t);
  }
  gl->set_lens(nullptr);
  return 0;
}
