// yuyv_to_rgba against the closed-form BT.601 float formula and against OpenCV's converter.
#include "drivers/convert/yuyv_to_rgba.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

namespace hd::drivers {
namespace {

// BT.601 limited range, exact coefficients (ITU-R BT.601: Kr = 0.299, Kb = 0.114).
std::array<int, 3> reference_rgb(int y, int u, int v) {
  const double c = (y - 16) * 255.0 / 219.0;
  const double d = (u - 128) * 255.0 / 224.0;
  const double e = (v - 128) * 255.0 / 224.0;
  const double r = c + 2.0 * (1 - 0.299) * e;
  const double g =
      c - 2.0 * 0.114 * (1 - 0.114) / 0.587 * d - 2.0 * 0.299 * (1 - 0.299) / 0.587 * e;
  const double b = c + 2.0 * (1 - 0.114) * d;
  auto q = [](double x) { return static_cast<int>(std::lround(std::clamp(x, 0.0, 255.0))); };
  return {q(r), q(g), q(b)};
}

std::vector<uint8_t> random_yuyv(std::mt19937& rng, int h, int stride) {
  std::vector<uint8_t> img(static_cast<std::size_t>(stride) * h);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& b : img) b = static_cast<uint8_t>(byte(rng));
  return img;
}

TEST(YuyvToRgba, KnownColoursMatchBt601LimitedRange) {
  // Y U Y V for: black, white (Y=235), and BT.601's 75%-free primary red (Y=81, Cb=90, Cr=240).
  const std::vector<uint8_t> src = {16, 128, 235, 128, 81, 90, 81, 240};
  std::vector<uint8_t> dst(4 * 4, 0);
  ASSERT_TRUE(yuyv_to_rgba(src.data(), src.size(), 4, 1, 8, dst.data(), dst.size(), 16));
  EXPECT_EQ((std::vector<int>{dst[0], dst[1], dst[2], dst[3]}), (std::vector<int>{0, 0, 0, 255}));
  EXPECT_EQ((std::vector<int>{dst[4], dst[5], dst[6], dst[7]}),
            (std::vector<int>{255, 255, 255, 255}));
  // Red from the float formula: R ~ 255, G ~ 0, B ~ 0 (within the 8-bit fixed point's 1 LSB).
  EXPECT_GE(dst[8], 254);
  EXPECT_LE(dst[9], 1);
  EXPECT_LE(dst[10], 1);
}

RC_GTEST_PROP(YuyvToRgba, WithinOneOfTheFloatFormula, ()) {
  const int w = 2 * *rc::gen::inRange(1, 17);
  const int h = *rc::gen::inRange(1, 9);
  const int pad = *rc::gen::inRange(0, 9);
  const int stride = 2 * w + pad;
  const auto bytes = *rc::gen::container<std::vector<uint8_t>>(static_cast<std::size_t>(stride * h),
                                                               rc::gen::arbitrary<uint8_t>());
  std::vector<uint8_t> dst(static_cast<std::size_t>(w) * 4 * h);
  RC_ASSERT(yuyv_to_rgba(bytes.data(), bytes.size(), w, h, stride, dst.data(), dst.size(), w * 4));
  for (int row = 0; row < h; ++row) {
    for (int x = 0; x < w; ++x) {
      const uint8_t* s = &bytes[static_cast<std::size_t>(row * stride + (x / 2) * 4)];
      const auto ref = reference_rgb(s[(x % 2) * 2], s[1], s[3]);
      const uint8_t* d = &dst[static_cast<std::size_t>((row * w + x) * 4)];
      for (int c = 0; c < 3; ++c) RC_ASSERT(std::abs(d[c] - ref[c]) <= 1);
      RC_ASSERT(d[3] == 255);
    }
  }
}

TEST(YuyvToRgba, AgreesWithOpenCv) {
  std::mt19937 rng(7);
  const int w = 64;
  const int h = 48;
  auto src = random_yuyv(rng, h, w * 2);
  // Keep inputs in the legal limited range, where both implementations promise BT.601.
  for (std::size_t i = 0; i < src.size(); ++i) {
    src[i] = (i % 2 == 0) ? static_cast<uint8_t>(16 + src[i] % 220)
                          : static_cast<uint8_t>(16 + src[i] % 225);
  }
  std::vector<uint8_t> ours(static_cast<std::size_t>(w) * h * 4);
  ASSERT_TRUE(yuyv_to_rgba(src.data(), src.size(), w, h, w * 2, ours.data(), ours.size(), w * 4));
  cv::Mat yuyv(h, w, CV_8UC2, src.data());
  cv::Mat rgba;
  cv::cvtColor(yuyv, rgba, cv::COLOR_YUV2RGBA_YUYV);
  ASSERT_TRUE(rgba.isContinuous());
  int worst = 0;
  for (std::size_t i = 0; i < ours.size(); ++i)
    worst = std::max(worst, std::abs(ours[i] - rgba.data[i]));
  EXPECT_LE(worst, 2) << "OpenCV and we both approximate BT.601 in fixed point";
}

TEST(YuyvToRgba, HonoursStridesAndLeavesPaddingAlone) {
  std::mt19937 rng(11);
  const int w = 6;
  const int h = 3;
  const int src_stride = 16;  // 12 bytes of pixels + 4 of padding
  const int dst_stride = 32;  // 24 bytes of pixels + 8 of padding
  auto src = random_yuyv(rng, h, src_stride);
  std::vector<uint8_t> dst(static_cast<std::size_t>(dst_stride) * h, 0xAB);
  // The last row needs only its own bytes, as drivers size buffers that way.
  const std::size_t src_len = static_cast<std::size_t>(src_stride) * (h - 1) + w * 2;
  ASSERT_TRUE(
      yuyv_to_rgba(src.data(), src_len, w, h, src_stride, dst.data(), dst.size(), dst_stride));
  for (int row = 0; row < h; ++row) {
    for (int x = 0; x < w; ++x) {
      const uint8_t* s = &src[static_cast<std::size_t>(row * src_stride + (x / 2) * 4)];
      const auto ref = reference_rgb(s[(x % 2) * 2], s[1], s[3]);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(dst[row * dst_stride + x * 4 + c], ref[c], 1);
    }
    for (int b = w * 4; b < dst_stride; ++b) EXPECT_EQ(dst[row * dst_stride + b], 0xAB);
  }
}

TEST(YuyvToRgba, RejectsInvalidInputWithoutWriting) {
  std::vector<uint8_t> src(64, 100);
  std::vector<uint8_t> dst(256, 0xCD);
  EXPECT_FALSE(yuyv_to_rgba(src.data(), src.size(), 3, 2, 8, dst.data(), dst.size(), 12));  // odd w
  EXPECT_FALSE(yuyv_to_rgba(src.data(), src.size(), 4, 0, 8, dst.data(), dst.size(), 16));  // h 0
  EXPECT_FALSE(
      yuyv_to_rgba(src.data(), src.size(), 4, 2, 6, dst.data(), dst.size(), 16));   // stride
  EXPECT_FALSE(yuyv_to_rgba(src.data(), 15, 4, 2, 8, dst.data(), dst.size(), 16));  // short src
  EXPECT_FALSE(yuyv_to_rgba(src.data(), src.size(), 4, 2, 8, dst.data(), 31, 16));  // short dst
  EXPECT_FALSE(yuyv_to_rgba(src.data(), src.size(), 4, 2, 8, dst.data(), dst.size(), 15));
  EXPECT_FALSE(yuyv_to_rgba(nullptr, src.size(), 4, 2, 8, dst.data(), dst.size(), 16));
  EXPECT_FALSE(yuyv_to_rgba(src.data(), src.size(), 4, 2, 8, nullptr, dst.size(), 16));
  EXPECT_FALSE(yuyv_to_rgba(src.data(), src.size(), -4, 2, 8, dst.data(), dst.size(), 16));
  EXPECT_TRUE(std::all_of(dst.begin(), dst.end(), [](uint8_t b) { return b == 0xCD; }));
  // Exactly enough is enough.
  EXPECT_TRUE(yuyv_to_rgba(src.data(), 16, 4, 2, 8, dst.data(), 32, 16));
}

}  // namespace
}  // namespace hd::drivers
