// The score run's error pictures: the error map's colours at its fixed scale (checked against
// OpenCV's INFERNO map directly), the scale bar, and the contact sheet's layout.
#include "station/app/score_pictures.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "support/solid_image.h"

namespace hd::station {
namespace {

render::ImageRgba8 filled(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  return testing::solid_image(w, h, r, g, b);
}

// INFERNO's colour at map index i, straight from OpenCV: the expectation does not go through
// the code under test.
cv::Vec3b inferno(int i) {
  cv::Mat index(1, 1, CV_8UC1, cv::Scalar(i)), colour;
  cv::applyColorMap(index, colour, cv::COLORMAP_INFERNO);
  return colour.at<cv::Vec3b>(0, 0);
}

bool all_pixels_are(const cv::Mat& m, cv::Vec3b c) {
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      if (m.at<cv::Vec3b>(y, x) != c) return false;
  return true;
}

TEST(ScorePictures, IdenticalPicturesMapUniformlyToTheZeroColour) {
  const render::ImageRgba8 a = filled(40, 30, 200, 10, 90);
  render::ImageRgba8 b = a;
  for (std::size_t i = 3; i < b.data.size(); i += 4) b.data[i] = 0;  // alpha is no error
  const cv::Mat map = error_map(b, a);
  ASSERT_EQ(map.type(), CV_8UC3);
  ASSERT_EQ(map.cols, 40);
  ASSERT_EQ(map.rows, 30);
  EXPECT_TRUE(all_pixels_are(map, inferno(0)));
  // The zero colour reads as "nothing": near black.
  const cv::Vec3b z = inferno(0);
  EXPECT_LT(z[0] + z[1] + z[2], 30);
}

TEST(ScorePictures, AKnownDifferenceMapsToItsColourOnTheFixedScale) {
  const render::ImageRgba8 truth = filled(8, 4, 100, 100, 100);
  render::ImageRgba8 shown = truth;
  // Column x differs by 8 x DN in one channel (green, then red, ...): e = 0, 8, ..., 56.
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) shown.pixel(x, y)[x % 3] = static_cast<uint8_t>(100 + 8 * x);
  // And a pixel past the full scale, below: it saturates at the map's top colour.
  shown.pixel(0, 3)[2] = 250;
  const cv::Mat map = error_map(shown, truth);
  for (int x = 0; x < 8; ++x) {
    // e DN sits at index round(e * 255 / 64) of the map: 32 DN at 128 (the middle).
    const int index = static_cast<int>(std::lround(8.0 * x * 255.0 / 64.0));
    EXPECT_EQ(map.at<cv::Vec3b>(0, x), inferno(index)) << "e = " << 8 * x;
    EXPECT_EQ(error_colour_bgr(8 * x), inferno(index));
  }
  EXPECT_EQ(map.at<cv::Vec3b>(3, 0), inferno(255));
  EXPECT_EQ(error_colour_bgr(64), inferno(255));
  EXPECT_EQ(error_colour_bgr(200), inferno(255));
  // The largest channel difference counts, not the sum: 10 and 20 DN in two channels is 20 DN.
  render::ImageRgba8 two = truth;
  two.pixel(0, 0)[0] = 110;
  two.pixel(0, 0)[1] = 80;
  EXPECT_EQ(error_map(two, truth).at<cv::Vec3b>(0, 0), error_colour_bgr(20));
}

TEST(ScorePictures, EmptyAndMismatchedPicturesAreSaidNotDrawn) {
  EXPECT_TRUE(error_map(render::ImageRgba8{}, render::ImageRgba8{}).empty());
  try {
    error_map(filled(4, 4, 0, 0, 0), filled(4, 5, 0, 0, 0));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("4x4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("4x5"), std::string::npos) << e.what();
  }
  EXPECT_THROW(score_contact_sheet({}), std::invalid_argument);
  EXPECT_THROW(score_contact_sheet({SheetRow{"nothing", {}, {}, {}}}), std::invalid_argument);
  const cv::Mat rgba(10, 10, CV_8UC4, cv::Scalar::all(0));
  EXPECT_THROW(score_contact_sheet({SheetRow{"rgba", rgba, rgba, rgba}}), std::invalid_argument);
  EXPECT_THROW(error_legend(63), std::invalid_argument);
}

TEST(ScorePictures, TheLegendRampsFromZeroToFullScale) {
  const cv::Mat bar = error_legend(300);
  ASSERT_EQ(bar.cols, 300);
  ASSERT_EQ(bar.rows, 36);
  EXPECT_EQ(bar.at<cv::Vec3b>(8, 0), error_colour_bgr(0));
  EXPECT_EQ(bar.at<cv::Vec3b>(8, 299), error_colour_bgr(64));
  // Its middle column is the middle of the scale (32 DN), give or take one column's step.
  const cv::Vec3b mid = bar.at<cv::Vec3b>(8, 150);
  EXPECT_TRUE(mid == error_colour_bgr(32) || mid == error_colour_bgr(33)) << mid;
}

// Three rows of 480 x 400 pictures: shown (red), truth (green), error (blue) land in their
// columns in every row, under the titles, with the legend under the error column.
TEST(ScorePictures, TheContactSheetHasThreeColumnsAndARowPerFrame) {
  const cv::Mat red(400, 480, CV_8UC3, cv::Scalar(0, 0, 255));
  const cv::Mat green(400, 480, CV_8UC3, cv::Scalar(0, 255, 0));
  const cv::Mat blue(400, 480, CV_8UC3, cv::Scalar(255, 0, 0));
  std::vector<SheetRow> rows;
  for (int i = 0; i < 3; ++i)
    rows.push_back(
        {"frame " + std::to_string(120 * i) + " eye 0 hybrid 28.4 dB", red, green, blue});
  const cv::Mat sheet = score_contact_sheet(rows);
  // 480 px tiles (3 x 480 + 4 x 6 px = 1464 px fits under 2000: not scaled); per row a 22 px
  // label, the tile and a 6 px gap; 26 px of titles on top and the 36 px legend at the bottom.
  constexpr int kPad = 6, kTitle = 26, kLabel = 22, kLegend = 36;
  EXPECT_EQ(sheet.cols, kPad + 3 * (480 + kPad));
  EXPECT_EQ(sheet.rows, kTitle + 3 * (kLabel + 400 + kPad) + kLegend + kPad);
  for (int r = 0; r < 3; ++r) {
    const int y = kTitle + r * (kLabel + 400 + kPad) + kLabel + 200;
    EXPECT_EQ(sheet.at<cv::Vec3b>(y, kPad + 240), cv::Vec3b(0, 0, 255)) << "row " << r;
    EXPECT_EQ(sheet.at<cv::Vec3b>(y, 2 * kPad + 480 + 240), cv::Vec3b(0, 255, 0));
    EXPECT_EQ(sheet.at<cv::Vec3b>(y, 3 * kPad + 960 + 240), cv::Vec3b(255, 0, 0));
  }
  // The legend's ramp starts at the error column's left edge.
  const int legend_y = kTitle + 3 * (kLabel + 400 + kPad) + 8;
  EXPECT_EQ(sheet.at<cv::Vec3b>(legend_y, 3 * kPad + 960), error_colour_bgr(0));
  // Titles and labels are drawn (something dark on the white bands).
  cv::Mat grey;
  cv::cvtColor(sheet(cv::Rect(0, 0, sheet.cols, kTitle)), grey, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::countNonZero(grey > 128), grey.rows * grey.cols);
  cv::cvtColor(sheet(cv::Rect(0, kTitle, sheet.cols, kLabel)), grey, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::countNonZero(grey > 128), grey.rows * grey.cols);
}

TEST(ScorePictures, WidePicturesAreScaledSoTheSheetStaysUnder2000Px) {
  const cv::Mat wide(900, 1600, CV_8UC3, cv::Scalar(10, 200, 30));
  const cv::Mat sheet = score_contact_sheet({{"a", wide, wide, wide}, {"b", wide, {}, wide}});
  EXPECT_LE(sheet.cols, kSheetMaxWidthPx);
  EXPECT_GE(sheet.cols, kSheetMaxWidthPx - 8);  // scaled to fit, not further
  // The missing truth of row b is a grey tile.
  const int tw = (kSheetMaxWidthPx - 4 * 6) / 3, th = 900 * tw / 1600;
  const int y = 26 + (22 + th + 6) + 22 + th / 2;
  EXPECT_EQ(sheet.at<cv::Vec3b>(y, 2 * 6 + tw + tw / 2), cv::Vec3b(128, 128, 128));
  EXPECT_EQ(sheet.at<cv::Vec3b>(y, 6 + tw / 2), cv::Vec3b(10, 200, 30));
}

}  // namespace
}  // namespace hd::station
