// RGB8 -> RGBA8 against OpenCV's RGB2RGBA and the closed form (r, g, b, 255).
#include "drivers/convert/rgb8_to_rgba.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

namespace hd::drivers {
namespace {

TEST(Rgb8ToRgba, MatchesOpenCvRgb2Rgba) {
  const int w = 31, h = 19;
  std::mt19937 rng(5);
  std::vector<uint8_t> src(static_cast<std::size_t>(w * h * 3));
  for (auto& v : src) v = static_cast<uint8_t>(rng());
  std::vector<uint8_t> out(static_cast<std::size_t>(w * h * 4), 0);
  ASSERT_TRUE(rgb8_to_rgba(src.data(), src.size(), w, h, 3 * w, out.data(), out.size(), w * 4));
  cv::Mat ref;
  cv::cvtColor(cv::Mat(h, w, CV_8UC3, src.data()), ref, cv::COLOR_RGB2RGBA);
  ASSERT_TRUE(ref.isContinuous());
  EXPECT_EQ(0, std::memcmp(out.data(), ref.data, out.size()));
}

TEST(Rgb8ToRgba, KeepsChannelOrderWithPaddedStrides) {
  const int w = 2, h = 2, src_stride = 8, dst_stride = 12;
  const std::vector<uint8_t> src = {10, 20, 30, 40, 50, 60, 0, 0, 70, 80, 90, 100, 110, 120};
  std::vector<uint8_t> out(static_cast<std::size_t>(dst_stride * (h - 1) + 4 * w), 0xCD);
  ASSERT_TRUE(
      rgb8_to_rgba(src.data(), src.size(), w, h, src_stride, out.data(), out.size(), dst_stride));
  const std::vector<uint8_t> expected = {10,   20,   30, 255, 40, 50,  60,  255, 0xCD, 0xCD,
                                         0xCD, 0xCD, 70, 80,  90, 255, 100, 110, 120,  255};
  EXPECT_EQ(out, expected);
}

TEST(Rgb8ToRgba, RejectsInvalidInputWithoutWriting) {
  std::vector<uint8_t> src(8 * 8 * 3, 1), dst(8 * 8 * 4, 7);
  EXPECT_FALSE(rgb8_to_rgba(nullptr, src.size(), 8, 8, 24, dst.data(), dst.size(), 32));
  EXPECT_FALSE(rgb8_to_rgba(src.data(), src.size(), 8, 8, 24, nullptr, dst.size(), 32));
  EXPECT_FALSE(rgb8_to_rgba(src.data(), src.size(), -1, 8, 24, dst.data(), dst.size(), 32));
  EXPECT_FALSE(rgb8_to_rgba(src.data(), src.size() - 1, 8, 8, 24, dst.data(), dst.size(), 32));
  EXPECT_FALSE(rgb8_to_rgba(src.data(), src.size(), 8, 8, 23, dst.data(), dst.size(), 32));
  EXPECT_FALSE(rgb8_to_rgba(src.data(), src.size(), 8, 8, 24, dst.data(), dst.size() - 1, 32));
  for (uint8_t v : dst) ASSERT_EQ(v, 7);
}

RC_GTEST_PROP(Rgb8ToRgbaProperty, CopiesChannelsAndAddsOpaqueAlpha,
              (const std::vector<uint8_t>& bytes)) {
  const int w = static_cast<int>(bytes.size() / 3);
  RC_PRE(w > 0);
  std::vector<uint8_t> out(static_cast<std::size_t>(w) * 4, 0);
  RC_ASSERT(rgb8_to_rgba(bytes.data(), bytes.size(), w, 1, 3 * w, out.data(), out.size(), 4 * w));
  for (int i = 0; i < w; ++i)
    for (int c = 0; c < 3; ++c)
      RC_ASSERT(out[static_cast<std::size_t>(4 * i + c)] ==
                bytes[static_cast<std::size_t>(3 * i + c)]);
}

}  // namespace
}  // namespace hd::drivers
