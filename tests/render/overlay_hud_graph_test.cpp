// The HUD's stage graph: the y scale's round top, each series drawn at its value's height in its
// own colour (measured on the drawn pixels against the plot's frame), and the strip that holds
// the graph below its text: taller while a graph is shown, re-drawn only when text or graph
// change.
#include "render/overlay/hud_graph.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "render/overlay/hud_strip.h"

namespace hd::render {
namespace {

TEST(HudGraph, TheScaleTopIsTheNextOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(round_scale_up(7.3), 10.0);
  EXPECT_DOUBLE_EQ(round_scale_up(10.0), 10.0);
  EXPECT_DOUBLE_EQ(round_scale_up(10.5), 20.0);
  EXPECT_DOUBLE_EQ(round_scale_up(38.0), 50.0);
  EXPECT_DOUBLE_EQ(round_scale_up(0.13), 0.2);
  EXPECT_DOUBLE_EQ(round_scale_up(1234.0), 2000.0);
  EXPECT_DOUBLE_EQ(round_scale_up(0.0), 1.0);
  EXPECT_DOUBLE_EQ(round_scale_up(NAN), 1.0);
}

// The rows of column x whose pixel is exactly colour c.
std::vector<int> rows_of(const cv::Mat& m, int x, const cv::Scalar& c) {
  std::vector<int> out;
  for (int y = 0; y < m.rows; ++y) {
    const cv::Vec4b p = m.at<cv::Vec4b>(y, x);
    if (p[0] == c[0] && p[1] == c[1] && p[2] == c[2]) out.push_back(y);
  }
  return out;
}

double mean(const std::vector<int>& v) {
  double s = 0;
  for (int y : v) s += y;
  return v.empty() ? NAN : s / double(v.size());
}

TEST(HudGraph, EachSeriesIsDrawnAtItsValuesHeightInItsColour) {
  HudGraph g;
  g.title = "cam: ms since capture";
  g.names = {"enc", "shown"};
  g.series = {std::vector<double>(10, 10.0), std::vector<double>(10, 15.0)};  // top: 20
  cv::Mat area(200, 500, CV_8UC4, cv::Scalar(0, 0, 0, 160));
  draw_hud_graph(area, g);
  const int x = 470;  // right in the plot, clear of the legend and the scale's labels
  const std::vector<int> frame = rows_of(area, x, cv::Scalar(150, 150, 150));
  ASSERT_GE(frame.size(), 2u);
  const double top = frame.front(), bottom = frame.back();
  const double enc = mean(rows_of(area, x, hud_graph_colour(0)));
  const double shown = mean(rows_of(area, x, hud_graph_colour(1)));
  ASSERT_FALSE(std::isnan(enc));
  ASSERT_FALSE(std::isnan(shown));
  // 15 ms three quarters up the plot, 10 ms halfway, within the 2 px line's width.
  EXPECT_NEAR(shown, bottom - 0.75 * (bottom - top), 1.5);
  EXPECT_NEAR(enc, (top + bottom) / 2, 1.5);
  // An empty graph draws nothing.
  cv::Mat blank(100, 200, CV_8UC4, cv::Scalar(0, 0, 0, 0));
  draw_hud_graph(blank, HudGraph{});
  EXPECT_EQ(cv::countNonZero(blank.reshape(1)), 0);
}

TEST(HudGraph, TheStripGrowsByTheGraphAndRedrawsOnlyOnAChange) {
  HudStrip strip(400, 20, 3, 5);
  EXPECT_EQ(strip.capacity_height(), 8 * 20);
  ASSERT_TRUE(strip.set_text("video  mtp 14 ms"));
  EXPECT_EQ(strip.image().height, 20);
  HudGraph g;
  g.title = "t";
  g.names = {"shown"};
  g.series = {{25.0, 26.0}};
  ASSERT_TRUE(strip.set_text("video  mtp 14 ms", g));
  EXPECT_TRUE(strip.shows_graph());
  EXPECT_EQ(strip.image().height, 20 + 5 * 20);
  const uint64_t revision = strip.revision();
  EXPECT_FALSE(strip.set_text("video  mtp 14 ms", g));  // nothing changed: not redrawn
  EXPECT_EQ(strip.revision(), revision);
  g.series[0].push_back(27.0);
  EXPECT_TRUE(strip.set_text("video  mtp 14 ms", g));
  EXPECT_TRUE(strip.set_text("video  mtp 14 ms"));  // the key again: the graph goes
  EXPECT_FALSE(strip.shows_graph());
  EXPECT_EQ(strip.image().height, 20);
  // A strip made without room for a graph never draws one.
  HudStrip small(400, 20, 3);
  small.set_text("x", g);
  EXPECT_EQ(small.image().height, 20);
}

}  // namespace
}  // namespace hd::render
