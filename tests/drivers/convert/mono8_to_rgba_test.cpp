// Mono8 -> RGBA8 against OpenCV's GRAY2RGBA and the closed form (v, v, v, 255).
#include "drivers/convert/mono8_to_rgba.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

namespace hd::drivers {
namespace {

TEST(Mono8ToRgba, MatchesOpenCvGray2Rgba) {
  const int w = 33, h = 17;
  std::mt19937 rng(3);
  std::vector<uint8_t> src(static_cast<std::size_t>(w * h));
  for (auto& v : src) v = static_cast<uint8_t>(rng());
  std::vector<uint8_t> out(static_cast<std::size_t>(w * h * 4), 0);
  ASSERT_TRUE(mono8_to_rgba(src.data(), src.size(), w, h, w, out.data(), out.size(), w * 4));
  cv::Mat ref;
  cv::cvtColor(cv::Mat(h, w, CV_8UC1, src.data()), ref, cv::COLOR_GRAY2RGBA);
  ASSERT_TRUE(ref.isContinuous());
  EXPECT_EQ(0, std::memcmp(out.data(), ref.data, out.size()));
}

TEST(Mono8ToRgba, HonoursPaddedStridesAndLeavesPaddingAlone) {
  const int w = 3, h = 2, src_stride = 5, dst_stride = 16;
  const std::vector<uint8_t> src = {1, 2, 3, 99, 99, 4, 5, 6};
  std::vector<uint8_t> out(static_cast<std::size_t>(dst_stride * (h - 1) + 4 * w), 0xAB);
  ASSERT_TRUE(
      mono8_to_rgba(src.data(), src.size(), w, h, src_stride, out.data(), out.size(), dst_stride));
  const std::vector<uint8_t> expected = {1, 1,   1,    255,  2,    2,    2, 255, 3, 3,
                                         3, 255, 0xAB, 0xAB, 0xAB, 0xAB, 4, 4,   4, 255,
                                         5, 5,   5,    255,  6,    6,    6, 255};
  EXPECT_EQ(out, expected);
}

TEST(Mono8ToRgba, RejectsInvalidInputWithoutWriting) {
  std::vector<uint8_t> src(8 * 8, 1), dst(8 * 8 * 4, 7);
  EXPECT_FALSE(mono8_to_rgba(nullptr, src.size(), 8, 8, 8, dst.data(), dst.size(), 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size(), 8, 8, 8, nullptr, dst.size(), 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size(), 0, 8, 8, dst.data(), dst.size(), 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size(), 8, 0, 8, dst.data(), dst.size(), 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size() - 1, 8, 8, 8, dst.data(), dst.size(), 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size(), 8, 8, 7, dst.data(), dst.size(), 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size(), 8, 8, 8, dst.data(), dst.size() - 1, 32));
  EXPECT_FALSE(mono8_to_rgba(src.data(), src.size(), 8, 8, 8, dst.data(), dst.size(), 31));
  for (uint8_t v : dst) ASSERT_EQ(v, 7);
}

RC_GTEST_PROP(Mono8ToRgbaProperty, EveryPixelIsGreyWithOpaqueAlpha,
              (const std::vector<uint8_t>& pixels)) {
  RC_PRE(!pixels.empty());
  const int w = static_cast<int>(pixels.size());
  std::vector<uint8_t> out(pixels.size() * 4, 0);
  RC_ASSERT(mono8_to_rgba(pixels.data(), pixels.size(), w, 1, w, out.data(), out.size(), 4 * w));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    RC_ASSERT(out[4 * i] == pixels[i]);
    RC_ASSERT(out[4 * i + 1] == pixels[i]);
    RC_ASSERT(out[4 * i + 2] == pixels[i]);
    RC_ASSERT(out[4 * i + 3] == 255);
  }
}

}  // namespace
}  // namespace hd::drivers
