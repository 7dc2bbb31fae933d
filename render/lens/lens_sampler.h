#pragma once
// The lens pass's sampler: one channel of the eyes' picture, bilinear with 8-bit weights on a
// 1/256 px grid (the CPU compositor's sampler), clamped to one eye. Every row kernel of
// CpuPredistorter (scalar, AVX2, AVX-512) performs exactly this integer arithmetic, so they give
// the same bytes.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace hd::render::lens {

// One channel of the eye image at the fixed-point position (X, Y) = 256 * (u - 0.5, v - 0.5)
// (pixel centres at +0.5), bilinear with 8-bit weights, clamped to the columns [x_lo, x_hi] and
// rows [0, y_hi] of the pixel's eye.
inline uint32_t sample_fixed(const uint8_t* base, int stride, int X, int Y, int channel, int x_lo,
                             int x_hi, int y_hi) {
  X = std::clamp(X, x_lo * 256, x_hi * 256 - 1);
  Y = std::clamp(Y, 0, y_hi * 256 - 1);
  const int x0 = X >> 8, y0 = Y >> 8;
  const uint32_t fx = static_cast<uint32_t>(X & 255), fy = static_cast<uint32_t>(Y & 255);
  const uint8_t* r0 = base + static_cast<std::ptrdiff_t>(y0) * stride + 4 * x0 + channel;
  const uint8_t* r1 = r0 + stride;
  const uint32_t top = r0[0] * (256 - fx) + r0[4] * fx;
  const uint32_t bottom = r1[0] * (256 - fx) + r1[4] * fx;
  return (top * (256 - fy) + bottom * fy + 32768) >> 16;
}

// The same at a continuous position.
inline uint32_t sample(const uint8_t* base, int stride, double u, double v, int channel, int x_lo,
                       int x_hi, int y_hi) {
  return sample_fixed(base, stride, static_cast<int>(std::floor((u - 0.5) * 256.0)),
                      static_cast<int>(std::floor((v - 0.5) * 256.0)), channel, x_lo, x_hi, y_hi);
}

}  // namespace hd::render::lens
