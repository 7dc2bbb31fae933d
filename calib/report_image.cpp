#include "calib/report_image.h"

#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace hd::calib {

cv::Mat render_report(const cv::Mat& background, const std::vector<View>& views,
                      const IntrinsicsResult& r, const Coverage& c) {
  const int W = r.image_size.width, H = r.image_size.height;
  const int legend_h = 90;
  cv::Mat out(H + legend_h, 2 * W, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::Mat left = out(cv::Rect(0, 0, W, H));
  if (!background.empty() && background.size() == r.image_size) {
    cv::Mat bg;
    cv::cvtColor(background, bg, cv::COLOR_GRAY2BGR);
    bg.convertTo(left, -1, 0.4, 100);  // dimmed so the vectors stand out
  }
  for (std::size_t i = 0; i < views.size() && i < r.views.size(); ++i) {
    const bool bad = r.views[i].outlier;
    for (std::size_t j = 0; j < views[i].corners.size(); ++j) {
      const cv::Point2f p = views[i].corners[j];
      const cv::Point2f e = r.views[i].residuals_px[j];
      const cv::Point2f q = p + e * static_cast<float>(kResidualMagnification);
      cv::circle(left, p, 1, bad ? cv::Scalar(0, 0, 255) : cv::Scalar(0, 140, 0), -1, cv::LINE_AA);
      cv::line(left, p, q, bad ? cv::Scalar(0, 0, 255) : cv::Scalar(200, 60, 0), 1, cv::LINE_AA);
    }
  }
  // Heat map: corners per cell, log-scaled so one corner is already visible.
  cv::Mat right = out(cv::Rect(W, 0, W, H));
  cv::Mat occ;
  c.occupancy.convertTo(occ, CV_32F);
  double mx = 0;
  cv::minMaxLoc(occ, nullptr, &mx);
  cv::Mat scaled;
  cv::log(occ + 1.0f, scaled);
  scaled = scaled * (255.0 / std::log(mx + 1.0 + 1e-9));
  scaled.convertTo(scaled, CV_8U);
  cv::Mat heat;
  cv::applyColorMap(scaled, heat, cv::COLORMAP_INFERNO);
  cv::resize(heat, right, right.size(), 0, 0, cv::INTER_NEAREST);
  for (int gy = 0; gy < c.occupancy.rows; ++gy)
    for (int gx = 0; gx < c.occupancy.cols; ++gx) {
      const cv::Point org(gx * W / c.occupancy.cols + 4, gy * H / c.occupancy.rows + 16);
      cv::putText(right, std::to_string(c.occupancy.at<int>(gy, gx)), org, cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    }
  char line1[256], line2[256], line3[256];
  std::snprintf(line1, sizeof line1,
                "Left: corners (green; red = outlier view) and residual vectors x%.0f (blue). "
                "RMS %.3f px, worst %s %.2f px",
                kResidualMagnification, r.rms_px,
                r.views[static_cast<std::size_t>(r.worst_view)].name.c_str(),
                r.views[static_cast<std::size_t>(r.worst_view)].rms_px);
  std::snprintf(line2, sizeof line2,
                "Right: corners per cell of an 8x6 grid (dark = none, bright = max %.0f). Hull "
                "covers %.0f%%, %.0f%% of cells used",
                mx, 100 * c.hull_fraction, 100 * c.grid_fraction);
  std::snprintf(line3, sizeof line3,
                "fx %.2f fy %.2f cx %.2f cy %.2f | board size %.0f-%.0f%% of image, tilt %.0f-%.0f "
                "deg",
                r.fx(), r.fy(), r.cx(), r.cy(), 100 * c.board_size_min, 100 * c.board_size_max,
                c.tilt_min_deg, c.tilt_max_deg);
  int y = H + 22;
  for (const char* s : {line1, line2, line3}) {
    cv::putText(out, s, cv::Point(8, y), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    y += 24;
  }
  return out;
}

}  // namespace hd::calib
