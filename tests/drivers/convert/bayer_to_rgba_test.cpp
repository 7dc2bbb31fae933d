// Bayer demosaic against closed forms (uniform colour, linear ramps) and against OpenCV's own
// bilinear demosaic (an independent implementation) on random mosaics.
#include "drivers/convert/bayer_to_rgba.h"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <array>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

namespace hd::drivers {
namespace {

constexpr std::array<PixelFormat, 4> kPatterns = {
    PixelFormat::kBayerRggb8, PixelFormat::kBayerGrbg8, PixelFormat::kBayerGbrg8,
    PixelFormat::kBayerBggr8};

// Channel (0 R, 1 G, 2 B) sampled at (x, y), written from the GenICam names (top-left first).
int channel_at(PixelFormat p, int x, int y) {
  const char* name = p == PixelFormat::kBayerRggb8   ? "RGGB"
                     : p == PixelFormat::kBayerGrbg8 ? "GRBG"
                     : p == PixelFormat::kBayerGbrg8 ? "GBRG"
                                                     : "BGGR";
  const char c = name[(x & 1) + 2 * (y & 1)];
  return c == 'R' ? 0 : c == 'G' ? 1 : 2;
}

// OpenCV names a mosaic by its second row's 2nd and 3rd pixels, so GenICam RGGB is its "BG".
int opencv_code(PixelFormat p) {
  switch (p) {
    case PixelFormat::kBayerRggb8:
      return cv::COLOR_BayerBG2RGB;
    case PixelFormat::kBayerGrbg8:
      return cv::COLOR_BayerGB2RGB;
    case PixelFormat::kBayerGbrg8:
      return cv::COLOR_BayerGR2RGB;
    default:
      return cv::COLOR_BayerRG2RGB;
  }
}

// Samples an RGB scene through the colour filter array.
template <class Scene>
std::vector<uint8_t> mosaic(PixelFormat p, int w, int h, Scene scene) {
  std::vector<uint8_t> m(static_cast<std::size_t>(w * h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      m[static_cast<std::size_t>(y * w + x)] = scene(x, y)[channel_at(p, x, y)];
  return m;
}

std::vector<uint8_t> demosaic(PixelFormat p, const std::vector<uint8_t>& m, int w, int h) {
  std::vector<uint8_t> out(static_cast<std::size_t>(w * h * 4), 0);
  EXPECT_TRUE(bayer_to_rgba(p, m.data(), m.size(), w, h, w, out.data(), out.size(), w * 4));
  return out;
}

TEST(BayerToRgba, UniformColourIsReproducedExactlyIncludingBorders) {
  const std::array<uint8_t, 3> colour = {200, 90, 17};
  for (PixelFormat p : kPatterns) {
    const int w = 7, h = 5;  // odd sizes: the last row/column start a new 2x2 cell
    const auto out = demosaic(p, mosaic(p, w, h, [&](int, int) { return colour; }), w, h);
    for (int i = 0; i < w * h; ++i) {
      ASSERT_EQ(out[4 * i + 0], 200) << to_string(p) << " pixel " << i;
      ASSERT_EQ(out[4 * i + 1], 90) << to_string(p) << " pixel " << i;
      ASSERT_EQ(out[4 * i + 2], 17) << to_string(p) << " pixel " << i;
      ASSERT_EQ(out[4 * i + 3], 255);
    }
  }
}

TEST(BayerToRgba, LinearRampIsExactInTheInteriorAndMirroredAtTheBorder) {
  // Bilinear interpolation of an affine scene at symmetric neighbours is exact: f(x) = mean of
  // f(x-1), f(x+1). At the border the mirrored neighbour stands in: f(0) estimated by f(1).
  const auto f = [](int x, int y) { return 10 + 4 * x + 6 * y; };
  const int w = 12, h = 9;
  for (PixelFormat p : kPatterns) {
    const auto out = demosaic(p,
                              mosaic(p, w, h,
                                     [&](int x, int y) {
                                       const auto v = static_cast<uint8_t>(f(x, y));
                                       return std::array<uint8_t, 3>{v, v, v};
                                     }),
                              w, h);
    for (int y = 1; y < h - 1; ++y)
      for (int x = 1; x < w - 1; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(out[static_cast<std::size_t>(4 * (y * w + x) + c)], f(x, y))
              << to_string(p) << " x=" << x << " y=" << y << " c=" << c;
    // Top-left corner: every missing sample comes from mirrored neighbours at x=1 and/or y=1.
    for (int c = 0; c < 3; ++c) {
      const int own = channel_at(p, 0, 0);
      int expected = f(0, 0);
      if (c != own) {
        const bool same_row = channel_at(p, 1, 0) == c;  // the left/right neighbour has it
        const bool same_col = channel_at(p, 0, 1) == c;
        // Green at a red/blue site: mean of 4 sides, two of them mirrored copies.
        expected = same_row && same_col ? (2 * f(1, 0) + 2 * f(0, 1) + 2) / 4
                   : same_row           ? f(1, 0)
                   : same_col           ? f(0, 1)
                                        : f(1, 1);
      }
      EXPECT_EQ(out[static_cast<std::size_t>(c)], expected) << to_string(p) << " c=" << c;
    }
  }
}

TEST(BayerToRgba, MatchesOpenCvBilinearOnRandomMosaicsInTheInterior) {
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> byte(0, 255);
  const int w = 64, h = 48;
  for (PixelFormat p : kPatterns) {
    std::vector<uint8_t> m(static_cast<std::size_t>(w * h));
    for (auto& v : m) v = static_cast<uint8_t>(byte(rng));
    const auto out = demosaic(p, m, w, h);
    cv::Mat ref;
    cv::cvtColor(cv::Mat(h, w, CV_8UC1, m.data()), ref, opencv_code(p));
    int max_diff = 0;
    // OpenCV copies its outermost rows/columns from their neighbours; compare where both
    // interpolate.
    for (int y = 1; y < h - 1; ++y)
      for (int x = 1; x < w - 1; ++x)
        for (int c = 0; c < 3; ++c) {
          const int a = out[static_cast<std::size_t>(4 * (y * w + x) + c)];
          const int b = ref.at<cv::Vec3b>(y, x)[c];
          max_diff = std::max(max_diff, std::abs(a - b));
        }
    EXPECT_LE(max_diff, 1) << to_string(p);  // rounding of the 4-sample mean may differ by 1
  }
}

TEST(BayerToRgba, OpenCvNamingMapsPureRedToRed) {
  // Guards the GenICam -> OpenCV name mapping used above with a scene whose answer is known.
  const int w = 8, h = 8;
  for (PixelFormat p : kPatterns) {
    auto m = mosaic(p, w, h, [](int, int) { return std::array<uint8_t, 3>{250, 0, 0}; });
    cv::Mat ref;
    cv::cvtColor(cv::Mat(h, w, CV_8UC1, m.data()), ref, opencv_code(p));
    EXPECT_EQ(ref.at<cv::Vec3b>(3, 3), cv::Vec3b(250, 0, 0)) << to_string(p);
  }
}

TEST(BayerToRgba, PaddedStridesGiveTheSameImage) {
  const int w = 10, h = 6, src_stride = 16, dst_stride = 48;
  std::mt19937 rng(7);
  std::vector<uint8_t> tight(static_cast<std::size_t>(w * h));
  for (auto& v : tight) v = static_cast<uint8_t>(rng());
  std::vector<uint8_t> padded(static_cast<std::size_t>(src_stride * (h - 1) + w), 0xEE);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      padded[static_cast<std::size_t>(y * src_stride + x)] =
          tight[static_cast<std::size_t>(y * w + x)];
  const auto expected = demosaic(PixelFormat::kBayerGbrg8, tight, w, h);
  std::vector<uint8_t> out(static_cast<std::size_t>(dst_stride * (h - 1) + 4 * w), 0);
  ASSERT_TRUE(bayer_to_rgba(PixelFormat::kBayerGbrg8, padded.data(), padded.size(), w, h,
                            src_stride, out.data(), out.size(), dst_stride));
  for (int y = 0; y < h; ++y)
    for (int i = 0; i < 4 * w; ++i)
      ASSERT_EQ(out[static_cast<std::size_t>(y * dst_stride + i)],
                expected[static_cast<std::size_t>(y * 4 * w + i)]);
}

TEST(BayerToRgba, RejectsInvalidInputWithoutWriting) {
  std::vector<uint8_t> src(16 * 16, 1), dst(16 * 16 * 4, 7);
  const auto untouched = [&] {
    for (uint8_t v : dst)
      if (v != 7) return false;
    return true;
  };
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kMono8, src.data(), src.size(), 16, 16, 16, dst.data(),
                             dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, nullptr, src.size(), 16, 16, 16, dst.data(),
                             dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, 16, 16, nullptr,
                             dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 1, 16, 16,
                             dst.data(), dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, 1, 16,
                             dst.data(), dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, -4, 16,
                             dst.data(), dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size() - 1, 16, 16, 16,
                             dst.data(), dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, 16, 15,
                             dst.data(), dst.size(), 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, 16, 16,
                             dst.data(), dst.size() - 1, 64));
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, 16, 16,
                             dst.data(), dst.size(), 63));
  EXPECT_TRUE(untouched());
  // Exactly sized buffers are accepted.
  EXPECT_TRUE(bayer_to_rgba(PixelFormat::kBayerRggb8, src.data(), src.size(), 16, 16, 16,
                            dst.data(), dst.size(), 64));
}

RC_GTEST_PROP(BayerToRgbaProperty, AnyUniformSceneAnySizeIsExact, ()) {
  const int w = *rc::gen::inRange(2, 40);
  const int h = *rc::gen::inRange(2, 40);
  const auto p = kPatterns[static_cast<std::size_t>(*rc::gen::inRange(0, 4))];
  const std::array<uint8_t, 3> colour = {*rc::gen::arbitrary<uint8_t>(),
                                         *rc::gen::arbitrary<uint8_t>(),
                                         *rc::gen::arbitrary<uint8_t>()};
  const auto m = mosaic(p, w, h, [&](int, int) { return colour; });
  std::vector<uint8_t> out(static_cast<std::size_t>(w * h * 4), 0);
  RC_ASSERT(bayer_to_rgba(p, m.data(), m.size(), w, h, w, out.data(), out.size(), w * 4));
  for (int i = 0; i < w * h; ++i)
    for (int c = 0; c < 3; ++c)
      RC_ASSERT(out[static_cast<std::size_t>(4 * i + c)] == colour[static_cast<std::size_t>(c)]);
}

}  // namespace
}  // namespace hd::drivers
