#pragma once
// What the station's PNG plots (trace.png, score_trace.png, m_scatter.png) share: a plot area with
// a value range, nice tick steps and labels in OpenCV's Hershey font.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <string>

namespace hd::station::plot {

/// A rectangle of the image showing [lo, hi] on one axis.
struct Axis {
  int from_px = 0, length_px = 1;  ///< where the axis starts and how long it is
  double lo = 0.0, hi = 1.0;
  bool flipped = false;  ///< a vertical axis: values grow upward (pixels downward)
  int px(double v) const {
    const double f = (std::clamp(v, lo, hi) - lo) / (hi - lo);
    const int d = static_cast<int>(std::lround(f * length_px));
    return flipped ? from_px + length_px - d : from_px + d;
  }
};

inline void text(cv::Mat& img, const std::string& s, cv::Point at, double scale = 0.45,
                 cv::Scalar colour = {0, 0, 0}) {
  cv::putText(img, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `count` ticks over `span`.
inline double tick_step(double span, int count) {
  const double raw = span / std::max(count, 1);
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= raw) return m * p;
  return 10.0 * p;
}

inline std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace hd::station::plot
