#include "station/app/score_plots.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "station/app/plot_axes.h"
#include "station/app/trace_plot.h"

namespace hd::station {
namespace {

constexpr int kLeft = 70, kRight = 20, kTop = 40, kBottom = 50;

// The PSNR axis: the finite values' range, widened to whole 5 dB steps.
plot::Axis psnr_axis(const std::vector<double>& values, int top, int height) {
  double lo = 100.0, hi = 0.0;
  for (double v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (lo > hi) lo = 0.0, hi = 50.0;
  lo = 5.0 * std::floor(lo / 5.0);
  hi = std::max(lo + 5.0, 5.0 * std::ceil(hi / 5.0));
  return {top, height, lo, hi, true};
}

void y_ticks(cv::Mat& img, const plot::Axis& y, const std::string& label) {
  const double step = plot::tick_step(y.hi - y.lo, 6);
  for (double v = y.lo; v <= y.hi + 1e-9; v += step) {
    cv::line(img, {kLeft - 5, y.px(v)}, {kLeft, y.px(v)}, cv::Scalar(0, 0, 0), 1);
    plot::text(img, plot::number(v), {8, y.px(v) + 5});
  }
  plot::text(img, label, {kLeft, kTop - 12}, 0.5);
}

void x_ticks(cv::Mat& img, const plot::Axis& x, int y_bottom, const std::string& label) {
  const double step = plot::tick_step(x.hi - x.lo, 10);
  for (double v = std::ceil(x.lo / step) * step; v <= x.hi + 1e-9; v += step) {
    cv::line(img, {x.px(v), y_bottom}, {x.px(v), y_bottom + 5}, cv::Scalar(0, 0, 0), 1);
    plot::text(img, plot::number(v), {x.px(v) - 10, y_bottom + 20});
  }
  plot::text(img, label, {x.from_px + x.length_px / 2 - 100, img.rows - 8}, 0.5);
}

}  // namespace

cv::Mat draw_score_trace(const std::vector<ScorePoint>& points, int width, int height) {
  if (points.empty()) throw std::invalid_argument("score trace: no frames");
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int w = width - kLeft - kRight, h = height - kTop - kBottom;
  const double t0 = points.front().t_s, t1 = std::max(points.back().t_s, t0 + 1e-3);
  const plot::Axis x{kLeft, w, t0, t1};
  std::vector<double> psnr;
  for (const ScorePoint& p : points) psnr.push_back(p.psnr_db);
  const plot::Axis y = psnr_axis(psnr, kTop, h);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int xa = x.px(points[i].t_s);
    const int xb = i + 1 < points.size() ? x.px(points[i + 1].t_s) : kLeft + w;
    cv::rectangle(img, cv::Rect(xa, kTop, std::max(xb - xa, 1), h),
                  variant_shade_bgr(points[i].variant), cv::FILLED);
  }
  std::vector<cv::Point> line;
  for (const ScorePoint& p : points)
    if (std::isfinite(p.psnr_db)) line.push_back({x.px(p.t_s), y.px(p.psnr_db)});
  cv::polylines(img, line, false, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::rectangle(img, cv::Rect(kLeft, kTop, w, h), cv::Scalar(0, 0, 0), 1);
  y_ticks(img, y,
          "PSNR of the shown picture against the truth [dB]; background: video green, hybrid "
          "yellow, synthetic red");
  x_ticks(img, x, kTop + h, "scene time of the display [s]");
  return img;
}

cv::Mat draw_m_scatter(const std::vector<ScorePoint>& points, double break_even_m, int width,
                       int height) {
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int w = width - kLeft - kRight, h = height - kTop - kBottom;
  std::vector<double> ms, psnr;
  for (const ScorePoint& p : points)
    if (std::isfinite(p.m)) {
      ms.push_back(p.m);
      psnr.push_back(p.pure_video_db);
      psnr.push_back(p.pure_synthetic_db);
    }
  // m up to its 95th percentile (a few frames far out would squeeze the rest into a corner).
  double m_hi = 100.0;
  if (!ms.empty()) {
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    m_hi = std::max(1.0, 1.1 * sorted[static_cast<std::size_t>(0.95 * (sorted.size() - 1))]);
  }
  const plot::Axis x{kLeft, w, 0.0, m_hi};
  const plot::Axis y = psnr_axis(psnr, kTop, h);
  for (const ScorePoint& p : points) {
    if (!std::isfinite(p.m)) continue;
    if (std::isfinite(p.pure_synthetic_db))
      cv::circle(img, {x.px(p.m), y.px(p.pure_synthetic_db)}, 2, cv::Scalar(150, 150, 150),
                 cv::FILLED);
    if (std::isfinite(p.pure_video_db))
      cv::circle(img, {x.px(p.m), y.px(p.pure_video_db)}, 2, cv::Scalar(60, 160, 40), cv::FILLED);
  }
  if (std::isfinite(break_even_m) && break_even_m <= m_hi) {
    const int xb = x.px(break_even_m);
    cv::line(img, {xb, kTop}, {xb, kTop + h}, cv::Scalar(0, 0, 200), 1);
    plot::text(img, "break-even m " + plot::number(std::round(10.0 * break_even_m) / 10.0),
               {xb + 5, kTop + 18}, 0.5, cv::Scalar(0, 0, 200));
  }
  cv::rectangle(img, cv::Rect(kLeft, kTop, w, h), cv::Scalar(0, 0, 0), 1);
  y_ticks(img, y, "PSNR of the same frame as pure video (green) and pure model (grey) [dB]");
  x_ticks(img, x, kTop + h, "m of the camera on screen (worse eye) [px]");
  return img;
}

}  // namespace hd::station
