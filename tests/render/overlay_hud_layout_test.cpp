// The HUD's layout: text that does not fit wraps at its separators or is shortened with "...",
// and no line is ever wider than the strip (issue 14: "... | video ag" cut off at the eye).
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "render/overlay/hud_strip.h"

namespace hd::render {
namespace {

// The drawn width of `s` at the strip's glyph size, measured with OpenCV directly.
int drawn_width(const std::string& s, int line_h) {
  int base = 0;
  const cv::Size unit = cv::getTextSize("Hg", cv::FONT_HERSHEY_SIMPLEX, 1.0, 1, &base);
  const double scale = 0.6 * line_h / (unit.height + base);
  return cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &base).width;
}

const std::string kLine =
    "synthetic  mtp p50 14.3 ms p95 22.9 ms | missed 0.08 % | video age 41.2 ms | model age 1.31 s";

TEST(HudLayout, FittingTextIsOneLineUnchanged) {
  const auto lines = HudStrip::layout("video  mtp 14 ms", 600, 20, 3);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "video  mtp 14 ms");
}

TEST(HudLayout, LongTextWrapsAtItsSeparatorsAndKeepsEveryWord) {
  const int width = 320, line_h = 20;
  ASSERT_GT(drawn_width(kLine, line_h), width);  // the case of the issue: too wide for the eye
  const auto lines = HudStrip::layout(kLine, width, line_h, 4);
  ASSERT_GE(lines.size(), 2u);
  std::string joined;
  for (const std::string& l : lines) {
    EXPECT_LE(drawn_width(l, line_h), width - 2 * HudStrip::kMarginPx) << l;
    joined += (joined.empty() ? "" : " ") + l;
    EXPECT_EQ(l.find("..."), std::string::npos);
    EXPECT_NE(l.back(), '|') << l;  // broken at a separator, which is not left dangling
  }
  // Broken at " | " where it can be: the second line starts with a field, not mid-word.
  EXPECT_EQ(lines[1].rfind("missed", 0) == 0 || lines[1].rfind("video", 0) == 0 ||
                lines[1].rfind("p95", 0) == 0,
            true)
      << lines[1];
  for (const char* word : {"synthetic", "missed", "video age", "model age 1.31 s"})
    EXPECT_NE(joined.find(word), std::string::npos) << word;
}

TEST(HudLayout, WhatDoesNotFitIsShortenedWithDotsNeverCut) {
  const int width = 200, line_h = 20;
  const auto lines = HudStrip::layout(kLine, width, line_h, 2);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1].substr(lines[1].size() - 3), "...");
  for (const std::string& l : lines) EXPECT_LE(drawn_width(l, line_h), width - 8) << l;
  // A single word wider than the strip is split, not drawn past the edge.
  const auto word = HudStrip::layout(std::string(60, 'W'), 100, 20, 1);
  ASSERT_EQ(word.size(), 1u);
  EXPECT_LE(drawn_width(word[0], 20), 100 - 8);
}

TEST(HudLayout, StripGrowsByLinesWithoutReallocating) {
  HudStrip hud(320, 20, 3);
  hud.set_text("short");
  EXPECT_EQ(hud.image().height, 20);
  const uint8_t* buffer = hud.image().data.data();
  hud.set_text(kLine);
  EXPECT_GE(hud.line_count(), 2);
  EXPECT_EQ(hud.image().height, 20 * hud.line_count());
  EXPECT_EQ(hud.image().data.data(), buffer);
  EXPECT_EQ(hud.capacity_height(), 60);
  // Glyph pixels on the second line: the text really is drawn there.
  int white = 0;
  for (int y = 20; y < 40; ++y)
    for (int x = 0; x < 320; ++x) white += hud.image().pixel(x, y)[0] > 200;
  EXPECT_GT(white, 20);
}

}  // namespace
}  // namespace hd::render
