#pragma once
// Fixed-point arithmetic on RGBA8 pixels packed in a uint32 (the CPU compositor's inner loops).

#include <bit>
#include <cstdint>

namespace hd::render {

static_assert(std::endian::native == std::endian::little, "packed RGBA assumes little-endian");

/// Lerps two packed RGBA8 pixels by f/256 (f in [0,255]), two channels per multiply, rounded to
/// nearest. Lanes cannot overflow: 255 * 256 + 128 < 65536. f = 0 returns `a` exactly.
inline uint32_t lerp_rgba(uint32_t a, uint32_t b, int f) {
  const uint32_t g = static_cast<uint32_t>(f), h = 256u - g;
  const uint32_t rb =
      ((((a & 0x00FF00FFu) * h + (b & 0x00FF00FFu) * g) + 0x00800080u) >> 8) & 0x00FF00FFu;
  const uint32_t ga =
      ((((a >> 8) & 0x00FF00FFu) * h + ((b >> 8) & 0x00FF00FFu) * g) + 0x00800080u) & 0xFF00FF00u;
  return rb | ga;
}

}  // namespace hd::render
