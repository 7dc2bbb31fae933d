#include "render/overlay/hud_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace hd::render {

bool HudGraph::operator==(const HudGraph& o) const {
  if (title != o.title || names != o.names || series.size() != o.series.size()) return false;
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (series[i].size() != o.series[i].size()) return false;
    for (std::size_t k = 0; k < series[i].size(); ++k) {
      const double a = series[i][k], b = o.series[i][k];
      if (!(a == b || (std::isnan(a) && std::isnan(b)))) return false;
    }
  }
  return true;
}

cv::Scalar hud_graph_colour(std::size_t i) {
  // Distinct on the HUD's dark background, in stage order: warm to cool.
  static const cv::Scalar kColours[] = {{255, 170, 60, 255},  {255, 230, 80, 255},
                                        {120, 230, 120, 255}, {90, 200, 255, 255},
                                        {200, 140, 255, 255}, {255, 255, 255, 255}};
  return kColours[i % (sizeof kColours / sizeof kColours[0])];
}

double round_scale_up(double v) {
  if (!(v > 0)) return 1.0;
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= v * (1 - 1e-12)) return m * decade;
  return 10.0 * decade;
}

void draw_hud_graph(cv::Mat& area, const HudGraph& g) {
  if (g.empty() || area.empty()) return;
  constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
  // Glyphs in proportion to the graph: about a tenth of its height, readable at 100 px.
  const double font = std::clamp(area.rows / 250.0, 0.35, 0.8);
  int baseline = 0;
  const int text_h = cv::getTextSize("Hg", kFont, font, 1, &baseline).height + baseline + 4;
  const cv::Scalar white(255, 255, 255, 255), grey(150, 150, 150, 255);
  double top = 0;
  for (const auto& s : g.series)
    for (double v : s)
      if (std::isfinite(v)) top = std::max(top, v);
  top = round_scale_up(top);
  // Plot: left margin for the scale, a title line above, a legend line below.
  const int left = cv::getTextSize("0000", kFont, font, 1, &baseline).width + 8;
  const int right = area.cols - 6;
  const int y0 = text_h + 2, y1 = area.rows - text_h - 2;
  if (right - left < 10 || y1 - y0 < 10) return;
  cv::putText(area, g.title, {left, text_h - 4}, kFont, font, white, 1, cv::LINE_AA);
  cv::rectangle(area, {left, y0}, {right, y1}, grey, 1);
  char label[32];
  std::snprintf(label, sizeof label, "%g", top);
  cv::putText(area, label, {4, y0 + text_h / 2}, kFont, font, grey, 1, cv::LINE_AA);
  cv::putText(area, "0", {4, y1}, kFont, font, grey, 1, cv::LINE_AA);
  const std::size_t n = g.series.front().size();
  auto at = [&](std::size_t k, double v) {
    const double x = n > 1 ? double(k) / double(n - 1) : 1.0;
    return cv::Point(left + static_cast<int>(std::lround(x * (right - left))),
                     y1 - static_cast<int>(std::lround(std::min(v, top) / top * (y1 - y0))));
  };
  std::string legend;
  int legend_x = left;
  for (std::size_t i = 0; i < g.series.size(); ++i) {
    const auto& s = g.series[i];
    const cv::Scalar c = hud_graph_colour(i);
    for (std::size_t k = 1; k < s.size() && k < n; ++k)
      if (std::isfinite(s[k - 1]) && std::isfinite(s[k]))
        cv::line(area, at(k - 1, s[k - 1]), at(k, s[k]), c, 2, cv::LINE_AA);
    if (s.size() == 1 && std::isfinite(s[0])) cv::circle(area, at(0, s[0]), 2, c, cv::FILLED);
    double newest = NAN;
    for (auto it = s.rbegin(); it != s.rend() && std::isnan(newest); ++it) newest = *it;
    const std::string name = i < g.names.size() ? g.names[i] : std::string("?");
    char entry[64];
    if (std::isfinite(newest))
      std::snprintf(entry, sizeof entry, "%s %.1f", name.c_str(), newest);
    else
      std::snprintf(entry, sizeof entry, "%s -", name.c_str());
    cv::putText(area, entry, {legend_x, area.rows - 6}, kFont, font, c, 1, cv::LINE_AA);
    legend_x += cv::getTextSize(entry, kFont, font, 1, &baseline).width + 12;
  }
}

}  // namespace hd::render
