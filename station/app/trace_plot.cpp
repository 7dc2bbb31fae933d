#include "station/app/trace_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "station/app/output_file.h"
#include "station/app/plot_axes.h"

namespace hd::station {
namespace {

using plot::number;
using plot::text;
using plot::tick_step;

constexpr int kLeft = 80, kRight = 20, kTop = 40, kGap = 50, kBottom = 50;

struct Panel {
  cv::Rect area;
  double y_lo, y_hi;
  int y_px(double v) const {
    const double f = (std::clamp(v, y_lo, y_hi) - y_lo) / (y_hi - y_lo);
    return area.y + area.height - static_cast<int>(std::lround(f * area.height));
  }
};

}  // namespace

cv::Scalar variant_shade_bgr(core::Variant v) {
  switch (v) {
    case core::Variant::kVideo:
      return {200, 238, 200};
    case core::Variant::kHybrid:
      return {165, 228, 250};
    case core::Variant::kSynthetic:
      return {200, 200, 250};
  }
  return {255, 255, 255};
}

cv::Mat draw_trace(const FrameLog& log, const core::TransitionParams& transition, int width,
                   int height) {
  if (log.size() == 0) throw std::invalid_argument("trace plot: no frames");
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const int plot_w = width - kLeft - kRight;
  const int panel_h = (height - kTop - kGap - kBottom) / 2;
  const double t0 = log[0].t_s;
  const double t1 = std::max(log[log.size() - 1].t_s, t0 + 1e-3);

  // The m axis shows the band with room above it; a run whose m stays far above it is
  // stretched up to a 95th percentile, so most of the curve stays readable.
  std::vector<double> finite;
  for (const FrameLogRow& r : log)
    if (std::isfinite(r.decision.m)) finite.push_back(r.decision.m);
  const double band_hi = transition.m_t + transition.eps;
  double m_hi = std::max(2.0 * band_hi, 1.0);
  if (!finite.empty()) {
    std::sort(finite.begin(), finite.end());
    const double p95 = finite[static_cast<std::size_t>(0.95 * (finite.size() - 1))];
    m_hi = std::clamp(1.15 * p95, m_hi, 10.0 * m_hi);
  }
  const Panel pm{{kLeft, kTop, plot_w, panel_h}, 0.0, m_hi};
  const Panel pw{{kLeft, kTop + panel_h + kGap, plot_w, panel_h}, 0.0, 1.0};
  auto x_px = [&](double t) {
    return kLeft + static_cast<int>(std::lround((t - t0) / (t1 - t0) * plot_w));
  };

  // Variant shading: each frame's span up to the next frame's start.
  for (std::size_t i = 0; i < log.size(); ++i) {
    const int xa = x_px(log[i].t_s);
    const int xb = i + 1 < log.size() ? x_px(log[i + 1].t_s) : kLeft + plot_w;
    if (xb <= xa && i + 1 < log.size()) continue;
    const cv::Scalar c = variant_shade_bgr(log[i].decision.variant);
    for (const Panel* p : {&pm, &pw})
      cv::rectangle(img, cv::Rect(xa, p->area.y, std::max(xb - xa, 1), p->area.height), c,
                    cv::FILLED);
  }

  // m_t +- eps band (translucent grey) and the m_t line.
  {
    cv::Mat overlay = img.clone();
    const int ya = pm.y_px(transition.m_t + transition.eps);
    const int yb = pm.y_px(std::max(transition.m_t - transition.eps, 0.0));
    cv::rectangle(overlay, cv::Rect(kLeft, ya, plot_w, std::max(yb - ya, 1)),
                  cv::Scalar(120, 120, 120), cv::FILLED);
    cv::addWeighted(overlay, 0.35, img, 0.65, 0.0, img);
    const int yt = pm.y_px(transition.m_t);
    for (int x = kLeft; x < kLeft + plot_w; x += 12)
      cv::line(img, {x, yt}, {std::min(x + 6, kLeft + plot_w), yt}, cv::Scalar(60, 60, 60), 1);
  }

  // Curves. Points above the m axis (and +inf) sit on its top edge, drawn red.
  std::vector<cv::Point> m_pts, w_pts;
  m_pts.reserve(log.size());
  w_pts.reserve(log.size());
  for (const FrameLogRow& r : log) {
    const int x = x_px(r.t_s);
    const double m = std::isfinite(r.decision.m) ? r.decision.m : m_hi;
    m_pts.push_back({x, pm.y_px(m)});
    w_pts.push_back({x, pw.y_px(r.decision.w_video)});
    if (!(r.decision.m <= m_hi)) cv::circle(img, {x, pm.area.y}, 1, cv::Scalar(0, 0, 200));
  }
  cv::polylines(img, m_pts, false, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::polylines(img, w_pts, false, cv::Scalar(170, 60, 0), 2, cv::LINE_AA);

  // Axes, ticks, labels.
  for (const Panel* p : {&pm, &pw}) {
    cv::rectangle(img, p->area, cv::Scalar(0, 0, 0), 1);
    const double step = tick_step(p->y_hi - p->y_lo, 5);
    for (double v = p->y_lo; v <= p->y_hi + 1e-9; v += step) {
      const int y = p->y_px(v);
      cv::line(img, {kLeft - 5, y}, {kLeft, y}, cv::Scalar(0, 0, 0), 1);
      text(img, number(v), {8, y + 5});
    }
    const double ts = tick_step(t1 - t0, 10);
    for (double t = std::ceil(t0 / ts) * ts; t <= t1 + 1e-9; t += ts) {
      const int x = x_px(t);
      cv::line(img, {x, p->area.y + p->area.height}, {x, p->area.y + p->area.height + 5},
               cv::Scalar(0, 0, 0), 1);
      text(img, number(t), {x - 10, p->area.y + p->area.height + 20});
    }
  }
  char title[200];
  std::snprintf(title, sizeof title,
                "m (worse eye, chosen camera) [px]; band m_t +- eps = %g +- %g; red dots: above "
                "axis or inf",
                transition.m_t, transition.eps);
  text(img, title, {kLeft, kTop - 12}, 0.5);
  text(img, "w_video (blue); background: video green, hybrid yellow, synthetic red",
       {kLeft, pw.area.y - 12}, 0.5);
  text(img, "time since the first frame [s]", {kLeft + plot_w / 2 - 110, height - 8}, 0.5);
  return img;
}

void write_trace_png(const FrameLog& log, const core::TransitionParams& transition,
                     const std::string& path) {
  write_png_atomically(draw_trace(log, transition), path);
}

}  // namespace hd::station
