#pragma once
// A small line graph for the operator's HUD (toggled on a key): a few named series sampled at
// the same ticks, oldest first, drawn below the HUD's text. The station's use: each stage's
// time since capture (p50 over the last second, one sample per HUD update), so the lines stack
// in stage order and the gap between two lines is that stage's delay.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hd::render {

struct HudGraph {
  std::string title;                        ///< what is plotted, with its unit
  std::vector<std::string> names;           ///< one per series, for the legend
  std::vector<std::vector<double>> series;  ///< same length each, oldest first; NaN: no sample

  bool empty() const { return series.empty() || series.front().empty(); }
  bool operator==(const HudGraph& o) const;
};

/// Draws `g` into `area` (CV_8UC4, opaque white lines and text on what is there): the title,
/// each series as a line in its own colour, the y scale from 0 to a round value above the
/// largest sample, and in the legend each series' newest value. Nothing when g is empty.
void draw_hud_graph(cv::Mat& area, const HudGraph& g);

/// The colour of series `i` (RGBA, opaque), shared by the line and its legend entry.
cv::Scalar hud_graph_colour(std::size_t i);

/// The smallest of 1, 2, 5 x 10^k that is >= v (the y scale's top); 1 for v <= 0 or NaN.
double round_scale_up(double v);

}  // namespace hd::render
