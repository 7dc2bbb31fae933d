// Randomized robustness run for the GigE converters (Mono8, RGB8, Bayer; the sanitizer build runs
// it too): random sizes, strides and lengths over random bytes. Pass = no crash, no sanitizer
// report, and both the accepting and the rejecting paths exercised.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "drivers/convert/bayer_to_rgba.h"
#include "drivers/convert/mono8_to_rgba.h"
#include "drivers/convert/rgb8_to_rgba.h"

namespace hd::drivers {
namespace {

struct Geometry {
  int w, h, src_stride, dst_stride;
  std::size_t src_len, dst_len, src_off, dst_off;
};

// Random geometry around the valid one for `bpp` source bytes per pixel: zero, negative and
// short strides and lengths, always inside the backing arrays so any overrun is the converter's.
Geometry random_geometry(std::mt19937_64& rng, int bpp, std::size_t src_cap, std::size_t dst_cap) {
  Geometry g{};
  g.w = static_cast<int>(rng() % 40) - 4;
  g.h = static_cast<int>(rng() % 20) - 2;
  g.src_stride = g.w * bpp + static_cast<int>(rng() % 9) - 2;
  g.dst_stride = g.w * 4 + static_cast<int>(rng() % 9) - 2;
  g.src_len = rng() % 4000;
  g.dst_len = rng() % 8000;
  g.src_off = rng() % (src_cap - g.src_len);
  g.dst_off = rng() % (dst_cap - g.dst_len);
  return g;
}

template <class Convert>
void fuzz(uint64_t seed, int bpp, int runs, Convert convert) {
  std::mt19937_64 rng(seed);
  std::vector<uint8_t> src(64 * 1024);
  std::vector<uint8_t> dst(128 * 1024);
  for (auto& b : src) b = static_cast<uint8_t>(rng());
  int accepted = 0;
  for (int i = 0; i < runs; ++i) {
    const Geometry g = random_geometry(rng, bpp, src.size(), dst.size());
    if (convert(src.data() + g.src_off, g.src_len, g.w, g.h, g.src_stride, dst.data() + g.dst_off,
                g.dst_len, g.dst_stride)) {
      ++accepted;
    }
  }
  EXPECT_GT(accepted, runs / 50);
  EXPECT_LT(accepted, runs);
}

TEST(ConverterFuzz, Mono8RandomGeometryAndBytes) {
  fuzz(0x111, 1, 300'000, mono8_to_rgba);
}

TEST(ConverterFuzz, Rgb8RandomGeometryAndBytes) {
  fuzz(0x222, 3, 300'000, rgb8_to_rgba);
}

TEST(ConverterFuzz, BayerRandomGeometryAndBytes) {
  const PixelFormat patterns[] = {PixelFormat::kBayerRggb8, PixelFormat::kBayerGrbg8,
                                  PixelFormat::kBayerGbrg8, PixelFormat::kBayerBggr8};
  uint64_t seed = 0x333;
  for (PixelFormat p : patterns) {
    fuzz(seed++, 1, 100'000,
         [p](const uint8_t* s, std::size_t sl, int w, int h, int ss, uint8_t* d, std::size_t dl,
             int ds) { return bayer_to_rgba(p, s, sl, w, h, ss, d, dl, ds); });
  }
  // A non-Bayer format is refused whatever the geometry.
  std::vector<uint8_t> src(64), dst(256);
  EXPECT_FALSE(bayer_to_rgba(PixelFormat::kYuyv, src.data(), src.size(), 4, 4, 4, dst.data(),
                             dst.size(), 16));
}

}  // namespace
}  // namespace hd::drivers
