#pragma once
// Fixed-point arithmetic on RGBA8 pixels packed in a uint32 (the CPU compositor's inner loops).

#include <bit>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

/// Bilinear sample of the 2x2 texels at p (p[0..7] one row, p + stride the next) with weights
/// fx/256, fy/256: lerp_rgba(lerp_rgba(c00, c10, fx), lerp_rgba(c01, c11, fx), fy) bit for bit
/// (same order, same rounding), four channels and both rows at once with SSE2 where available.
inline uint32_t bilinear_rgba(const uint8_t* p, long stride, int fx, int fy) {
#if defined(__SSE2__)
  const __m128i zero = _mm_setzero_si128();
  const __m128i r0 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));           // c00 c10
  const __m128i r1 = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p + stride));  // c01 c11
  const __m128i left_right = _mm_unpacklo_epi32(r0, r1);      // c00 c01 c10 c11
  const __m128i left = _mm_unpacklo_epi8(left_right, zero);   // c00 c01, 16-bit lanes
  const __m128i right = _mm_unpackhi_epi8(left_right, zero);  // c10 c11
  const __m128i round = _mm_set1_epi16(128);
  // left (256 - fx) + right fx as left 256 + (right - left) fx: the true value lies in
  // [0, 255 * 256], so the 16-bit wrap-around of the subtraction and product cancels out.
  const __m128i rows = _mm_srli_epi16(
      _mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(left, 8),
                                  _mm_mullo_epi16(_mm_sub_epi16(right, left),
                                                  _mm_set1_epi16(static_cast<short>(fx)))),
                    round),
      8);  // top (c00..c10) in lanes 0-3, bottom (c01..c11) in lanes 4-7
  const __m128i bottom = _mm_srli_si128(rows, 8);  // the same way between the two rows
  const __m128i sum = _mm_srli_epi16(
      _mm_add_epi16(_mm_add_epi16(_mm_slli_epi16(rows, 8),
                                  _mm_mullo_epi16(_mm_sub_epi16(bottom, rows),
                                                  _mm_set1_epi16(static_cast<short>(fy)))),
                    round),
      8);
  return static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_packus_epi16(sum, zero)));
#else
  uint32_t c00, c10, c01, c11;
  std::memcpy(&c00, p, 4);
  std::memcpy(&c10, p + 4, 4);
  std::memcpy(&c01, p + stride, 4);
  std::memcpy(&c11, p + stride + 4, 4);
  return lerp_rgba(lerp_rgba(c00, c10, fx), lerp_rgba(c01, c11, fx), fy);
#endif
}

}  // namespace hd::render
