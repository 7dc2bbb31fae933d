#pragma once
// Bilinear, clamp-to-edge texture lookups with the conventions both compositors share.

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace hd::render {

/// Samples an RGBA8 image at continuous pixel position (u, v) (pixel centres at +0.5), bilinear
/// between the four nearest texel centres, edges clamped — what GL_LINEAR + GL_CLAMP_TO_EDGE does
/// for a texture coordinate (u / width, v / height). Writes RGB to rgb[0..2] as floats in [0,255].
inline void sample_bilinear(const uint8_t* data, int width, int height, int stride_bytes, float u,
                            float v, float* rgb) {
  const float x = u - 0.5f;
  const float y = v - 0.5f;
  const float xf = std::floor(x);
  const float yf = std::floor(y);
  const float ax = x - xf;
  const float ay = y - yf;
  // Clamp in float first: a far-off coordinate must not overflow the int conversion.
  const int x0 = static_cast<int>(std::clamp(xf, -1.0f, static_cast<float>(width)));
  const int y0 = static_cast<int>(std::clamp(yf, -1.0f, static_cast<float>(height)));
  const int xa = std::clamp(x0, 0, width - 1);
  const int xb = std::clamp(x0 + 1, 0, width - 1);
  const int ya = std::clamp(y0, 0, height - 1);
  const int yb = std::clamp(y0 + 1, 0, height - 1);
  const uint8_t* r0 = data + static_cast<long>(ya) * stride_bytes;
  const uint8_t* r1 = data + static_cast<long>(yb) * stride_bytes;
  for (int c = 0; c < 3; ++c) {
    const float top = r0[4 * xa + c] + ax * (static_cast<float>(r0[4 * xb + c]) - r0[4 * xa + c]);
    const float bot = r1[4 * xa + c] + ax * (static_cast<float>(r1[4 * xb + c]) - r1[4 * xa + c]);
    rgb[c] = top + ay * (bot - top);
  }
}

}  // namespace hd::render
