#include "render/lens/cpu_predistorter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__x86_64__)
#include <immintrin.h>
#define HD_LENS_AVX2 1
#endif

namespace hd::render::lens {
namespace {

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

#if HD_LENS_AVX2
// (d * s) >> 16 per lane, exactly as the scalar int64 arithmetic: the products are formed in 64
// bits (even and odd lanes), and the low 32 bits of a logical shift equal an arithmetic one's.
__attribute__((target("avx2"))) inline __m256i scale_16_16(__m256i d, __m256i s) {
  const __m256i even = _mm256_srli_epi64(_mm256_mul_epi32(d, s), 16);
  const __m256i odd = _mm256_srli_epi64(_mm256_mul_epi32(_mm256_srli_epi64(d, 32), s), 16);
  return _mm256_blend_epi32(even, _mm256_slli_epi64(odd, 32), 0xAA);
}

// One channel of the 8 texels at `i`.
__attribute__((target("avx2"))) inline __m256i fetch8(const int* base, __m256i i, int shift) {
  return _mm256_and_si256(
      _mm256_srl_epi32(_mm256_i32gather_epi32(base, i, 4), _mm_cvtsi32_si128(shift)),
      _mm256_set1_epi32(255));
}

// sample_fixed for 8 pixels at once (the same integer arithmetic, so the same bytes).
__attribute__((target("avx2"))) inline __m256i sample8(const int* base, int stride4, __m256i X,
                                                       __m256i Y, int channel, __m256i x_min,
                                                       __m256i x_max, __m256i y_max) {
  X = _mm256_min_epi32(_mm256_max_epi32(X, x_min), x_max);
  Y = _mm256_min_epi32(_mm256_max_epi32(Y, _mm256_setzero_si256()), y_max);
  const __m256i m255 = _mm256_set1_epi32(255), m256 = _mm256_set1_epi32(256);
  const __m256i fx = _mm256_and_si256(X, m255), fy = _mm256_and_si256(Y, m255);
  const __m256i idx =
      _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srai_epi32(Y, 8), _mm256_set1_epi32(stride4)),
                       _mm256_srai_epi32(X, 8));
  const __m256i one = _mm256_set1_epi32(1), row = _mm256_set1_epi32(stride4);
  const int shift = 8 * channel;
  const __m256i a = fetch8(base, idx, shift), b = fetch8(base, _mm256_add_epi32(idx, one), shift);
  const __m256i below = _mm256_add_epi32(idx, row);
  const __m256i c = fetch8(base, below, shift);
  const __m256i d = fetch8(base, _mm256_add_epi32(below, one), shift);
  const __m256i wx = _mm256_sub_epi32(m256, fx), wy = _mm256_sub_epi32(m256, fy);
  const __m256i top = _mm256_add_epi32(_mm256_mullo_epi32(a, wx), _mm256_mullo_epi32(b, fx));
  const __m256i bottom = _mm256_add_epi32(_mm256_mullo_epi32(c, wx), _mm256_mullo_epi32(d, fx));
  const __m256i sum = _mm256_add_epi32(
      _mm256_add_epi32(_mm256_mullo_epi32(top, wy), _mm256_mullo_epi32(bottom, fy)),
      _mm256_set1_epi32(32768));
  return _mm256_srli_epi32(sum, 16);
}

// Pixels [x, end) of one row and eye, 8 at a time; returns where it stopped (end - (end - x) % 8).
__attribute__((target("avx2"))) int span_avx2(const uint8_t* base, int stride, const int32_t* pos,
                                              uint32_t* out, int x, int end, int CX, int CY,
                                              int32_t sr, int32_t sb, int x_lo, int x_hi,
                                              int y_hi) {
  const int* b32 = reinterpret_cast<const int*>(base);
  const int stride4 = stride / 4;
  const __m256i cx = _mm256_set1_epi32(CX), cy = _mm256_set1_epi32(CY);
  const __m256i vsr = _mm256_set1_epi32(sr), vsb = _mm256_set1_epi32(sb);
  const __m256i x_min = _mm256_set1_epi32(x_lo * 256), x_max = _mm256_set1_epi32(x_hi * 256 - 1);
  const __m256i y_max = _mm256_set1_epi32(y_hi * 256 - 1);
  const __m256i alpha = _mm256_set1_epi32(static_cast<int>(0xFF000000u));
  for (; x + 8 <= end; x += 8) {
    // Deinterleave (X, Y) pairs of 8 pixels.
    const __m256i p0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(pos + 2 * x));
    const __m256i p1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(pos + 2 * x + 8));
    const __m256i perm = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    const __m256i q0 = _mm256_permutevar8x32_epi32(p0, perm);
    const __m256i q1 = _mm256_permutevar8x32_epi32(p1, perm);
    const __m256i X = _mm256_permute2x128_si256(q0, q1, 0x20);
    const __m256i Y = _mm256_permute2x128_si256(q0, q1, 0x31);
    const __m256i dX = _mm256_sub_epi32(X, cx), dY = _mm256_sub_epi32(Y, cy);
    const __m256i XR = _mm256_add_epi32(cx, scale_16_16(dX, vsr));
    const __m256i YR = _mm256_add_epi32(cy, scale_16_16(dY, vsr));
    const __m256i XB = _mm256_add_epi32(cx, scale_16_16(dX, vsb));
    const __m256i YB = _mm256_add_epi32(cy, scale_16_16(dY, vsb));
    const __m256i r = sample8(b32, stride4, XR, YR, 0, x_min, x_max, y_max);
    const __m256i g = sample8(b32, stride4, X, Y, 1, x_min, x_max, y_max);
    const __m256i bl = sample8(b32, stride4, XB, YB, 2, x_min, x_max, y_max);
    const __m256i px = _mm256_or_si256(_mm256_or_si256(r, _mm256_slli_epi32(g, 8)),
                                       _mm256_or_si256(_mm256_slli_epi32(bl, 16), alpha));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + x), px);
  }
  return x;
}

// --- kRadial ---------------------------------------------------------------------------------

// Where one channel of 8 pixels samples, ready for the fetch: the gather indices of the top-left
// texels (lanes reordered {0, 1, 4, 5, 2, 3, 6, 7}, see fetch8_pairs), the horizontal weights as
// 16-bit words (256 - fx, fx) and fy.
struct Taps8 {
  __m256i idx, wx, fy;
};

template <bool kClamp>
__attribute__((target("avx2,fma"))) inline Taps8 taps8(int stride4, __m256i X, __m256i Y,
                                                       __m256i x_min, __m256i x_max,
                                                       __m256i y_max) {
  if (kClamp) {
    X = _mm256_min_epi32(_mm256_max_epi32(X, x_min), x_max);
    Y = _mm256_min_epi32(_mm256_max_epi32(Y, _mm256_setzero_si256()), y_max);
  }
  const __m256i m255 = _mm256_set1_epi32(255);
  const __m256i idx =
      _mm256_add_epi32(_mm256_mullo_epi32(_mm256_srai_epi32(Y, 8), _mm256_set1_epi32(stride4)),
                       _mm256_srai_epi32(X, 8));
  const __m256i fx = _mm256_and_si256(X, m255);
  return {_mm256_permutevar8x32_epi32(idx, _mm256_setr_epi32(0, 1, 4, 5, 2, 3, 6, 7)),
          _mm256_sub_epi32(_mm256_add_epi32(_mm256_slli_epi32(fx, 16), _mm256_set1_epi32(256)), fx),
          _mm256_and_si256(Y, m255)};
}

// sample_fixed for 8 pixels at once, each pair of horizontally adjacent texels fetched by one
// 64-bit gather lane and weighed by pmaddwd (the same integer arithmetic, so the same bytes:
// top * (256 - fy) + bottom * fy = 256 * top + (bottom - top) * fy).
// `pick_lo` / `pick_hi` move the channel's two bytes of each pair (RGBA RGBA) into 16-bit words:
// the gathers of lanes {0, 1, 4, 5} fill the low 8 bytes of each 128-bit lane, those of
// {2, 3, 6, 7} the high 8, which puts the pixels back in order.
// `below` is `base` one row on: the same indices fetch the bottom pairs.
__attribute__((target("avx2,fma"))) inline __m256i fetch8_pairs(const long long* base,
                                                                const long long* below,
                                                                const Taps8& t, __m256i pick_lo,
                                                                __m256i pick_hi) {
  const __m128i lo = _mm256_castsi256_si128(t.idx), hi = _mm256_extracti128_si256(t.idx, 1);
  const __m256i t_lo = _mm256_i32gather_epi64(base, lo, 4);
  const __m256i t_hi = _mm256_i32gather_epi64(base, hi, 4);
  const __m256i b_lo = _mm256_i32gather_epi64(below, lo, 4);
  const __m256i b_hi = _mm256_i32gather_epi64(below, hi, 4);
  const __m256i top_w =
      _mm256_or_si256(_mm256_shuffle_epi8(t_lo, pick_lo), _mm256_shuffle_epi8(t_hi, pick_hi));
  const __m256i bottom_w =
      _mm256_or_si256(_mm256_shuffle_epi8(b_lo, pick_lo), _mm256_shuffle_epi8(b_hi, pick_hi));
  const __m256i top = _mm256_madd_epi16(top_w, t.wx);
  const __m256i bottom = _mm256_madd_epi16(bottom_w, t.wx);
  const __m256i sum =
      _mm256_add_epi32(_mm256_add_epi32(_mm256_slli_epi32(top, 8),
                                        _mm256_mullo_epi32(_mm256_sub_epi32(bottom, top), t.fy)),
                       _mm256_set1_epi32(32768));
  return _mm256_srli_epi32(sum, 16);
}

struct RadialArgs {
  const uint8_t* base;
  int stride;
  const float* ratio;
  int ratio_terms;
  float d0x, kx, dy, ry2;  // row constants: dy = float(y) + d0[1], ry2 = (dy * k[1])^2
  const float (*gain256)[2];
  const float* origin256;
  int x_lo, x_hi, y_hi;
};

// Panel columns [x, end) of one row and eye (x - half_offset = the column in the half), in chunks
// of up to kChunk groups of 8: first every sample point of the chunk (into a small buffer on the
// stack, in L1), then the fetches. Two short dependency chains instead of one long one let the
// core overlap more groups' gathers. The last partial group is computed whole and stored under
// a mask (its extra lanes are clamped into the eye like any other sample, so they read inside
// the image).
template <bool kClamp>
__attribute__((target("avx2,fma"))) void radial_span_avx2(const RadialArgs& a, uint32_t* out, int x,
                                                          int end, int half_offset) {
  constexpr int kChunk = 16;
  const long long* b64 = reinterpret_cast<const long long*>(a.base);
  const long long* b64_below = reinterpret_cast<const long long*>(a.base + a.stride);
  const int stride4 = a.stride / 4;
  const __m256i x_min = _mm256_set1_epi32(a.x_lo * 256),
                x_max = _mm256_set1_epi32(a.x_hi * 256 - 1);
  const __m256i y_max = _mm256_set1_epi32(a.y_hi * 256 - 1);
  const __m256i alpha = _mm256_set1_epi32(static_cast<int>(0xFF000000u));
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256 d0x = _mm256_set1_ps(a.d0x), kx = _mm256_set1_ps(a.kx);
  const __m256 dy = _mm256_set1_ps(a.dy), ry2 = _mm256_set1_ps(a.ry2);
  const __m256 top_coeff = _mm256_set1_ps(a.ratio[a.ratio_terms - 1]);
  __m256i pick_lo[3], pick_hi[3];
  for (int c = 0; c < 3; ++c) {
    const char z = -128;  // pshufb: zero
    const char b0 = static_cast<char>(c), b1 = static_cast<char>(c + 4),
               b2 = static_cast<char>(c + 8), b3 = static_cast<char>(c + 12);
    pick_lo[c] = _mm256_setr_epi8(b0, z, b1, z, b2, z, b3, z, z, z, z, z, z, z, z, z,  //
                                  b0, z, b1, z, b2, z, b3, z, z, z, z, z, z, z, z, z);
    pick_hi[c] = _mm256_setr_epi8(z, z, z, z, z, z, z, z, b0, z, b1, z, b2, z, b3, z,  //
                                  z, z, z, z, z, z, z, z, b0, z, b1, z, b2, z, b3, z);
  }
  __m256 gx[3], gy[3];
  for (int c = 0; c < 3; ++c) {
    gx[c] = _mm256_set1_ps(a.gain256[c][0]);
    gy[c] = _mm256_set1_ps(a.gain256[c][1]);
  }
  const __m256 ox = _mm256_set1_ps(a.origin256[0]), oy = _mm256_set1_ps(a.origin256[1]);
  Taps8 taps[kChunk][3];
  while (x < end) {
    const int groups = std::min(kChunk, (end - x + 7) / 8);
    for (int g = 0; g < groups; ++g) {
      const __m256i col = _mm256_add_epi32(_mm256_set1_epi32(x + 8 * g - half_offset), iota);
      const __m256 dx = _mm256_add_ps(_mm256_cvtepi32_ps(col), d0x);
      const __m256 rx = _mm256_mul_ps(dx, kx);
      const __m256 r = _mm256_sqrt_ps(_mm256_fmadd_ps(rx, rx, ry2));
      __m256 t = top_coeff;
      for (int i = a.ratio_terms - 2; i >= 0; --i)
        t = _mm256_fmadd_ps(t, r, _mm256_set1_ps(a.ratio[i]));
      const __m256 ax = _mm256_mul_ps(t, dx), ay = _mm256_mul_ps(t, dy);
      for (int c = 0; c < 3; ++c)
        taps[g][c] =
            taps8<kClamp>(stride4, _mm256_cvttps_epi32(_mm256_fmadd_ps(ax, gx[c], ox)),
                          _mm256_cvttps_epi32(_mm256_fmadd_ps(ay, gy[c], oy)), x_min, x_max, y_max);
    }
    for (int g = 0; g < groups; ++g, x += 8) {
      const __m256i r = fetch8_pairs(b64, b64_below, taps[g][0], pick_lo[0], pick_hi[0]);
      const __m256i gr = fetch8_pairs(b64, b64_below, taps[g][1], pick_lo[1], pick_hi[1]);
      const __m256i bl = fetch8_pairs(b64, b64_below, taps[g][2], pick_lo[2], pick_hi[2]);
      const __m256i px = _mm256_or_si256(_mm256_or_si256(r, _mm256_slli_epi32(gr, 8)),
                                         _mm256_or_si256(_mm256_slli_epi32(bl, 16), alpha));
      if (end - x >= 8) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + x), px);
      } else {
        const __m256i keep = _mm256_cmpgt_epi32(_mm256_set1_epi32(end - x), iota);
        _mm256_maskstore_epi32(reinterpret_cast<int*>(out + x), keep, px);
      }
    }
  }
}

// The AVX-512 (F, BW, VBMI) form of radial_span_avx2: 16 pixels per group, a 64-bit gather lane
// per texel pair in pixel order (8 per instruction), and one vpermt2b per row of texels picking
// the channel's two bytes of all 16 pairs into 16-bit words. The same integer arithmetic.
// GCC 12 warns that its own _mm512_undefined_* pass-through operands of the unmasked
// conversions and square root "may be used uninitialized" (a false positive in the headers).
#pragma GCC diagnostic push
#if !defined(__clang__)  // clang has no -Wmaybe-uninitialized and does not warn here
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#pragma GCC diagnostic ignored "-Wuninitialized"
struct Taps16 {
  __m512i idx, wx, fy;
};

template <bool kClamp>
__attribute__((target("avx512f,avx512bw,avx512vbmi,avx2,fma"))) void radial_span_avx512(
    const RadialArgs& a, uint32_t* out, int x, int end, int half_offset) {
  constexpr int kChunk = 8;
  const int stride4 = a.stride / 4;
  const __m512i x_min = _mm512_set1_epi32(a.x_lo * 256),
                x_max = _mm512_set1_epi32(a.x_hi * 256 - 1);
  const __m512i y_max = _mm512_set1_epi32(a.y_hi * 256 - 1);
  const __m512i zero = _mm512_setzero_si512(), m255 = _mm512_set1_epi32(255);
  const __m512i alpha = _mm512_set1_epi32(static_cast<int>(0xFF000000u));
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512 d0x = _mm512_set1_ps(a.d0x), kx = _mm512_set1_ps(a.kx);
  const __m512 dy = _mm512_set1_ps(a.dy), ry2 = _mm512_set1_ps(a.ry2);
  const __m512 top_coeff = _mm512_set1_ps(a.ratio[a.ratio_terms - 1]);
  __m512 gx[3], gy[3];
  __m512i pick[3];  // per pixel p: bytes 8p + c and 8p + 4 + c of the two gathered registers
  for (int c = 0; c < 3; ++c) {
    gx[c] = _mm512_set1_ps(a.gain256[c][0]);
    gy[c] = _mm512_set1_ps(a.gain256[c][1]);
    alignas(64) uint8_t sel[64];
    for (int p = 0; p < 16; ++p) {
      sel[4 * p] = static_cast<uint8_t>(8 * p + c);
      sel[4 * p + 1] = 0;
      sel[4 * p + 2] = static_cast<uint8_t>(8 * p + 4 + c);
      sel[4 * p + 3] = 0;
    }
    pick[c] = _mm512_load_si512(sel);
  }
  const __mmask64 even_bytes = 0x5555555555555555ull;
  const __m512 ox = _mm512_set1_ps(a.origin256[0]), oy = _mm512_set1_ps(a.origin256[1]);
  const __m512i stride4v = _mm512_set1_epi32(stride4);
  Taps16 taps[kChunk][3];
  while (x < end) {
    const int groups = std::min(kChunk, (end - x + 15) / 16);
    for (int g = 0; g < groups; ++g) {
      const __m512i col = _mm512_add_epi32(_mm512_set1_epi32(x + 16 * g - half_offset), iota);
      const __m512 dx = _mm512_add_ps(_mm512_cvtepi32_ps(col), d0x);
      const __m512 rx = _mm512_mul_ps(dx, kx);
      const __m512 r = _mm512_sqrt_ps(_mm512_fmadd_ps(rx, rx, ry2));
      __m512 t = top_coeff;
      for (int i = a.ratio_terms - 2; i >= 0; --i)
        t = _mm512_fmadd_ps(t, r, _mm512_set1_ps(a.ratio[i]));
      const __m512 ax = _mm512_mul_ps(t, dx), ay = _mm512_mul_ps(t, dy);
      for (int c = 0; c < 3; ++c) {
        __m512i X = _mm512_cvttps_epi32(_mm512_fmadd_ps(ax, gx[c], ox));
        __m512i Y = _mm512_cvttps_epi32(_mm512_fmadd_ps(ay, gy[c], oy));
        if (kClamp) {
          X = _mm512_min_epi32(_mm512_max_epi32(X, x_min), x_max);
          Y = _mm512_min_epi32(_mm512_max_epi32(Y, zero), y_max);
        }
        const __m512i fx = _mm512_and_si512(X, m255);
        taps[g][c].idx = _mm512_add_epi32(_mm512_mullo_epi32(_mm512_srai_epi32(Y, 8), stride4v),
                                          _mm512_srai_epi32(X, 8));
        taps[g][c].wx = _mm512_sub_epi32(
            _mm512_add_epi32(_mm512_slli_epi32(fx, 16), _mm512_set1_epi32(256)), fx);
        taps[g][c].fy = _mm512_and_si512(Y, m255);
      }
    }
    for (int g = 0; g < groups; ++g, x += 16) {
      __m512i ch[3];
      for (int c = 0; c < 3; ++c) {
        const Taps16& tp = taps[g][c];
        const __m256i lo = _mm512_castsi512_si256(tp.idx),
                      hi = _mm512_extracti64x4_epi64(tp.idx, 1);
        const __m512i t0 = _mm512_i32gather_epi64(lo, a.base, 4);
        const __m512i t1 = _mm512_i32gather_epi64(hi, a.base, 4);
        const __m512i b0 = _mm512_i32gather_epi64(lo, a.base + a.stride, 4);
        const __m512i b1 = _mm512_i32gather_epi64(hi, a.base + a.stride, 4);
        const __m512i top_w = _mm512_maskz_permutex2var_epi8(even_bytes, t0, pick[c], t1);
        const __m512i bottom_w = _mm512_maskz_permutex2var_epi8(even_bytes, b0, pick[c], b1);
        const __m512i top = _mm512_madd_epi16(top_w, tp.wx);
        const __m512i bottom = _mm512_madd_epi16(bottom_w, tp.wx);
        const __m512i sum = _mm512_add_epi32(
            _mm512_add_epi32(_mm512_slli_epi32(top, 8),
                             _mm512_mullo_epi32(_mm512_sub_epi32(bottom, top), tp.fy)),
            _mm512_set1_epi32(32768));
        ch[c] = _mm512_srli_epi32(sum, 16);
      }
      const __m512i rg = _mm512_or_si512(ch[0], _mm512_slli_epi32(ch[1], 8));
      const __m512i px = _mm512_ternarylogic_epi32(rg, _mm512_slli_epi32(ch[2], 16), alpha, 0xFE);
      if (end - x >= 16) {
        _mm512_storeu_si512(out + x, px);
      } else {
        const __mmask16 keep = static_cast<__mmask16>((1u << (end - x)) - 1u);
        _mm512_mask_storeu_epi32(out + x, keep, px);
      }
    }
  }
}

#pragma GCC diagnostic pop

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
}

bool cpu_has_avx512() {
  static const bool has = cpu_has_avx2() && __builtin_cpu_supports("avx512f") &&
                          __builtin_cpu_supports("avx512bw") &&
                          __builtin_cpu_supports("avx512vbmi");
  return has;
}
#endif

bool sizes_fit(const LensWarp& w, const ImageRgba8& eyes, const ImageRgba8& panel) {
  return eyes.width >= 2 * w.eye_width() && eyes.height >= w.eye_height() &&
         eyes.stride_bytes % 4 == 0 && panel.width == w.panel_width() &&
         panel.height == w.panel_height() &&
         eyes.data.size() >= static_cast<std::size_t>(eyes.stride_bytes) * eyes.height &&
         panel.data.size() >= static_cast<std::size_t>(panel.stride_bytes) * panel.height;
}

}  // namespace

CpuPredistorter::CpuPredistorter(const LensWarp& warp, int threads, Simd simd, Method method)
    : warp_(warp),
      method_(method),
      threads_(std::clamp(threads, 1, 2)),
      rows_(threads_, RowWorker::Split::kClaimed, kRowsPerTake, /*spin=*/true) {
#if HD_LENS_AVX2
  if (simd != Simd::kNone && cpu_has_avx2()) simd_ = Simd::kAvx2;
  if (simd == Simd::kBest && method_ == Method::kRadial && cpu_has_avx512()) simd_ = Simd::kAvx512;
#else
  (void)simd;
#endif
  const int pw = warp_.panel_width(), ph = warp_.panel_height(), hw = warp_.eye_panel_width();
  const int ew = warp_.eye_width();
  spans_.assign(static_cast<std::size_t>(ph) * 2, Span{});
  for (int y = 0; y < ph; ++y) {
    for (int e = 0; e < 2; ++e) {
      Span& s = spans_[static_cast<std::size_t>(y) * 2 + e];
      s.begin = s.end = e * hw;
      bool open = false;
      for (int x = 0; x < hw; ++x) {
        double u = 0.0, v = 0.0;
        if (!warp_.source(e, x + 0.5, y + 0.5, 1, &u, &v)) continue;
        // The usable region is a disc cut by the half: one span per row.
        if (!open) s.begin = e * hw + x;
        open = true;
        s.end = e * hw + x + 1;
      }
    }
  }
  const std::vector<double>& k = warp_.profile().coefficients;
  ratio_terms_ = std::clamp(static_cast<int>(k.size()) - 1, 1, kMaxRatioTerms);
  for (int i = 0; i < ratio_terms_; ++i)
    ratio_[i] = static_cast<float>(static_cast<std::size_t>(i) + 1 < k.size() ? k[i + 1] : 0.0);
  for (int e = 0; e < 2; ++e) {
    const LensWarp::PanelMap m = warp_.panel_map(e);
    RadialEye& r = radial_[e];
    for (int a = 0; a < 2; ++a) {
      r.d0[a] = static_cast<float>(0.5 - m.centre_px[a]);
      r.k[a] = static_cast<float>(m.r_per_px[a]);
      for (int c = 0; c < 3; ++c)
        r.gain256[c][a] = static_cast<float>(256.0 * m.gain[static_cast<std::size_t>(c)][a]);
    }
    r.origin256[0] = static_cast<float>(256.0 * (warp_.eye(e).cx + e * ew - 0.5));
    r.origin256[1] = static_cast<float>(256.0 * (warp_.eye(e).cy - 0.5));
  }

  // A span whose every sample point, including the extra lanes of its last group of 16, lies
  // where the clamp leaves it unchanged runs the kernels without the clamp (the same bytes).
  for (int y = 0; y < ph; ++y)
    for (int e = 0; e < 2; ++e) {
      Span& s = spans_[static_cast<std::size_t>(y) * 2 + e];
      const float x_min = 256.0f * static_cast<float>(e * ew),
                  x_max = 256.0f * static_cast<float>(e * ew + ew - 1);
      const float y_max = 256.0f * static_cast<float>(warp_.eye_height() - 1);
      const int len = s.end - s.begin;
      bool inside = len > 0;
      for (int x = s.begin; inside && x < s.begin + (len + 15) / 16 * 16; ++x) {
        float X[3], Y[3];
        radial_points(y, e, x - e * hw, X, Y);
        for (int c = 0; c < 3; ++c)
          inside = inside && X[c] >= x_min && X[c] < x_max && Y[c] >= 0.0f && Y[c] < y_max;
      }
      s.clamp_free = inside;
    }

  for (int c = 0; c < 3; ++c)
    scale_fixed_[c] = static_cast<int32_t>(std::lround(warp_.channel_scale(c) * 65536.0));
  for (int e = 0; e < 2; ++e) {
    centre_fixed_[e][0] =
        static_cast<int32_t>(std::lround((warp_.eye(e).cx + e * ew - 0.5) * 256.0));
    centre_fixed_[e][1] = static_cast<int32_t>(std::lround((warp_.eye(e).cy - 0.5) * 256.0));
  }
  if (method_ == Method::kPositionTable) {
    positions_.assign(static_cast<std::size_t>(pw) * ph * 2, 0);
    for (int y = 0; y < ph; ++y)
      for (int e = 0; e < 2; ++e) {
        const Span& s = spans_[static_cast<std::size_t>(y) * 2 + e];
        for (int x = s.begin; x < s.end; ++x) {
          double u = 0.0, v = 0.0;
          warp_.source_unclamped(e, x - e * hw + 0.5, y + 0.5, 1, &u, &v);
          const std::size_t i = (static_cast<std::size_t>(y) * pw + x) * 2;
          positions_[i] = static_cast<int32_t>(std::floor((u + e * ew - 0.5) * 256.0));
          positions_[i + 1] = static_cast<int32_t>(std::floor((v - 0.5) * 256.0));
        }
      }
  }
}

CpuPredistorter::~CpuPredistorter() = default;

bool CpuPredistorter::apply(const ImageRgba8& eyes, ImageRgba8& panel) {
  if (!sizes_fit(warp_, eyes, panel)) return false;
  eyes_ = &eyes;
  panel_ = &panel;
  auto rows = [this](int row_begin, int row_end, int) { band(row_begin, row_end); };
  rows_.run(warp_.panel_height(), rows);
  eyes_ = nullptr;
  panel_ = nullptr;
  return true;
}

void CpuPredistorter::radial_points(int y, int e, int x_half, float* X, float* Y) const {
  // The AVX2 / AVX-512 kernels' arithmetic, operation for operation (std::fma rounds once, like
  // vfmadd; the kernels square ry in scalar code too).
  const RadialEye& r = radial_[e];
  const float dy = static_cast<float>(y) + r.d0[1];
  const float ry = dy * r.k[1];
  const float ry2 = ry * ry;
  const float dx = static_cast<float>(x_half) + r.d0[0];
  const float rx = dx * r.k[0];
  const float rr = std::sqrt(std::fma(rx, rx, ry2));
  float t = ratio_[ratio_terms_ - 1];
  for (int i = ratio_terms_ - 2; i >= 0; --i) t = std::fma(t, rr, ratio_[i]);
  const float ax = t * dx, ay = t * dy;
  for (int c = 0; c < 3; ++c) {
    X[c] = std::fma(ax, r.gain256[c][0], r.origin256[0]);
    Y[c] = std::fma(ay, r.gain256[c][1], r.origin256[1]);
  }
}

void CpuPredistorter::radial_span_scalar(int y, int e, int x, int end, uint32_t* out) const {
  const int ew = warp_.eye_width(), half = e * warp_.eye_panel_width();
  const int x_lo = e * ew, x_hi = e * ew + ew - 1, y_hi = warp_.eye_height() - 1;
  const uint8_t* base = eyes_->data.data();
  const int stride = eyes_->stride_bytes;
  for (; x < end; ++x) {
    float X[3], Y[3];
    radial_points(y, e, x - half, X, Y);
    uint32_t px = 0xFF000000u;
    for (int c = 0; c < 3; ++c)
      px |= sample_fixed(base, stride, static_cast<int>(X[c]), static_cast<int>(Y[c]), c, x_lo,
                         x_hi, y_hi)
            << (8 * c);
    out[x] = px;
  }
}

void CpuPredistorter::table_span_scalar(int y, int e, int x, int end, uint32_t* out) const {
  const int ew = warp_.eye_width();
  const int x_lo = e * ew, x_hi = e * ew + ew - 1, y_hi = warp_.eye_height() - 1;
  const uint8_t* base = eyes_->data.data();
  const int stride = eyes_->stride_bytes;
  const int32_t* pos = positions_.data() + static_cast<std::size_t>(y) * warp_.panel_width() * 2;
  const int CX = centre_fixed_[e][0], CY = centre_fixed_[e][1];
  const int64_t sr = scale_fixed_[0], sb = scale_fixed_[2];
  for (; x < end; ++x) {
    const int X = pos[2 * x], Y = pos[2 * x + 1];
    const int64_t dX = X - CX, dY = Y - CY;
    const int XR = CX + static_cast<int>((dX * sr) >> 16),
              YR = CY + static_cast<int>((dY * sr) >> 16);
    const int XB = CX + static_cast<int>((dX * sb) >> 16),
              YB = CY + static_cast<int>((dY * sb) >> 16);
    const uint32_t r = sample_fixed(base, stride, XR, YR, 0, x_lo, x_hi, y_hi);
    const uint32_t g = sample_fixed(base, stride, X, Y, 1, x_lo, x_hi, y_hi);
    const uint32_t b = sample_fixed(base, stride, XB, YB, 2, x_lo, x_hi, y_hi);
    out[x] = r | (g << 8) | (b << 16) | 0xFF000000u;
  }
}

void CpuPredistorter::band(int row_begin, int row_end) {
  const int hw = warp_.eye_panel_width(), ew = warp_.eye_width();
  for (int y = row_begin; y < row_end; ++y) {
    uint32_t* out = reinterpret_cast<uint32_t*>(panel_->row(y));
    int x = 0;
    for (int e = 0; e < 2; ++e) {
      const Span s = spans_[static_cast<std::size_t>(y) * 2 + e];
      for (; x < s.begin; ++x) out[x] = 0xFF000000u;  // opaque black (RGBA bytes 0, 0, 0, 255)
      if (method_ == Method::kRadial) {
#if HD_LENS_AVX2
        if (simd_ != Simd::kNone) {
          const RadialEye& r = radial_[e];
          const float dy = static_cast<float>(y) + r.d0[1];
          const float ry = dy * r.k[1];
          const RadialArgs a{eyes_->data.data(),
                             eyes_->stride_bytes,
                             ratio_,
                             ratio_terms_,
                             r.d0[0],
                             r.k[0],
                             dy,
                             ry * ry,
                             r.gain256,
                             r.origin256,
                             e * ew,
                             e * ew + ew - 1,
                             warp_.eye_height() - 1};
          if (simd_ == Simd::kAvx512)
            (s.clamp_free ? radial_span_avx512<false> : radial_span_avx512<true>)(a, out, x, s.end,
                                                                                  e * hw);
          else
            (s.clamp_free ? radial_span_avx2<false> : radial_span_avx2<true>)(a, out, x, s.end,
                                                                              e * hw);
          x = s.end;
        }
#endif
        radial_span_scalar(y, e, x, s.end, out);
      } else {
#if HD_LENS_AVX2
        if (simd_ != Simd::kNone) {
          const int32_t* pos =
              positions_.data() + static_cast<std::size_t>(y) * warp_.panel_width() * 2;
          x = span_avx2(eyes_->data.data(), eyes_->stride_bytes, pos, out, x, s.end,
                        centre_fixed_[e][0], centre_fixed_[e][1], scale_fixed_[0], scale_fixed_[2],
                        e * ew, e * ew + ew - 1, warp_.eye_height() - 1);
        }
#endif
        table_span_scalar(y, e, x, s.end, out);
      }
      x = std::max(x, s.end);
      for (; x < (e + 1) * hw; ++x) out[x] = 0xFF000000u;
    }
  }
}

int CpuPredistorter::clamp_free_spans() const {
  return static_cast<int>(
      std::count_if(spans_.begin(), spans_.end(), [](const Span& s) { return s.clamp_free; }));
}

void CpuPredistorter::sample_point(int e, int x, int y, int c, double* u, double* v) const {
  const int ew = warp_.eye_width();
  if (method_ == Method::kRadial) {
    float X[3], Y[3];
    radial_points(y, e, x, X, Y);
    *u = X[c] / 256.0 + 0.5 - e * ew;
    *v = Y[c] / 256.0 + 0.5;
    return;
  }
  const std::size_t i =
      (static_cast<std::size_t>(y) * warp_.panel_width() + e * warp_.eye_panel_width() + x) * 2;
  const int64_t dX = positions_[i] - centre_fixed_[e][0],
                dY = positions_[i + 1] - centre_fixed_[e][1];
  const int X = centre_fixed_[e][0] + static_cast<int>((dX * scale_fixed_[c]) >> 16);
  const int Y = centre_fixed_[e][1] + static_cast<int>((dY * scale_fixed_[c]) >> 16);
  *u = X / 256.0 + 0.5 - e * ew;
  *v = Y / 256.0 + 0.5;
}

bool CpuPredistorter::apply_exact(const ImageRgba8& eyes, ImageRgba8& panel) const {
  if (!sizes_fit(warp_, eyes, panel)) return false;
  const int hw = warp_.eye_panel_width(), ew = warp_.eye_width();
  for (int y = 0; y < warp_.panel_height(); ++y) {
    uint32_t* out = reinterpret_cast<uint32_t*>(panel.row(y));
    for (int e = 0; e < 2; ++e) {
      for (int x = 0; x < hw; ++x) {
        uint32_t px = 0xFF000000u;
        for (int c = 0; c < 3; ++c) {
          double u = 0.0, v = 0.0;
          if (!warp_.source(e, x + 0.5, y + 0.5, c, &u, &v)) break;
          px |= sample(eyes.data.data(), eyes.stride_bytes, u + e * ew, v, c, e * ew,
                       e * ew + ew - 1, warp_.eye_height() - 1)
                << (8 * c);
        }
        out[e * hw + x] = px;
      }
    }
  }
  return true;
}

}  // namespace hd::render::lens
