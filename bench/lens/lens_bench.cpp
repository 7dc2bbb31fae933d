// hybrid-bench-lens: what pre-distortion costs per frame beside the geometric error it leaves,
// measured against the exact per-pixel lens model, in one run.
//
//   CPU: the lookup table (1 and 2 threads) vs evaluating the polynomial per pixel and channel;
//        peers: OpenCV cv::remap with the same sample points (one map per channel, 3 passes) and
//        with the green map only (no chromatic correction).
//   GL (needs a display: xvfb-run for llvmpipe): the distortion mesh at several resolutions.
//
// The case is two 800x600 eye halves of a panel (1600x600) behind the OSVR HDK 1.3's lens
// polynomial with the DK1's chromatic aberration, so every channel has its own sample points.

#include <algorithm>
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

#include "render/gl/gl_compositor.h"
#include "render/lens/cpu_predistorter.h"
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

}  // namespace

int main(int argc, char** argv) {
  const int runs = argc > 1 ? std::max(3, std::atoi(argv[1])) : 21;
  const LensWarp warp(bench_profile());
  const ImageRgba8 eyes = eyes_pattern(warp);
  std::printf(
      "hybrid-bench-lens: panel %dx%d (two 800x600 eye halves), eye images %dx%d, %d runs\n",
      warp.panel_width(), warp.panel_height(), warp.eye_width(), warp.eye_height(), runs);

  ImageRgba8 exact, table1, table2;
  for (ImageRgba8* i : {&exact, &table1, &table2})
    i->allocate(warp.panel_width(), warp.panel_height());
  CpuPredistorter pd1(warp, 1), pd2(warp, 2);
  const Maps maps = make_maps(warp);

  const Timing t_exact = time_it(std::max(3, runs / 4), [&] { pd1.apply_exact(eyes, exact); });
  const Timing t1 = time_it(runs, [&] { pd1.apply(eyes, table1); });
  const Timing t2 = time_it(runs, [&] { pd2.apply(eyes, table2); });

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

  std::printf(
      "\n| CPU pre-distortion, 1600x600 panel | max geometric error px | RMS levels vs exact | "
      "median ms | min ms | CPU ms |\n|---|---|---|---|---|---|\n");
  auto row = [](const char* name, double geo, double rms, const Timing& t) {
    std::printf("| %s | %.2g | %.3f | %.3f | %.3f | %.3f |\n", name, geo, rms, t.wall_ms, t.min_ms,
                t.cpu_ms);
  };
  row("exact per-pixel polynomial, 1 thread (reference)", 0.0, 0.0, t_exact);
  row("**lookup table, 1 thread**", maps.table_error_px, rms_levels(table1, exact), t1);
  row("**lookup table, 2 threads**", maps.table_error_px, rms_levels(table2, exact), t2);
  row("peer: OpenCV remap per channel (3 maps), 1 thread", maps.table_error_px,
      rms_levels(cv_img, exact), t_cv3);
  row("peer: OpenCV remap, green map for all channels, 1 thread", maps.green_only_error_px,
      std::nan(""), t_cv1);
  std::printf(
      "\nTable / exact time: %.3f (1 thread), %.3f (2 threads); table / OpenCV 3-map remap: %.2f\n",
      t1.wall_ms / t_exact.wall_ms, t2.wall_ms / t_exact.wall_ms, t1.wall_ms / t_cv3.wall_ms);
  return 0;
}
