#include "render/lens/predistort_kernels.h"

#if HD_LENS_AVX2
#include <immintrin.h>

#include <algorithm>

namespace hd::render::lens::kernels {
namespace {

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
__attribute__((target("avx2"))) int table_span_avx2_impl(const uint8_t* base, int stride,
                                                         const int32_t* pos, uint32_t* out, int x,
                                                         int end, int CX, int CY, int32_t sr,
                                                         int32_t sb, int x_lo, int x_hi, int y_hi) {
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

// Panel columns [x, end) of one row and eye (x - half_offset = the column in the half), in chunks
// of up to kChunk groups of 8: first every sample point of the chunk (into a small buffer on the
// stack, in L1), then the fetches. Two short dependency chains instead of one long one let the
// core overlap more groups' gathers. The last partial group is computed whole and stored under
// a mask (its extra lanes are clamped into the eye like any other sample, so they read inside
// the image).
template <bool kClamp>
__attribute__((target("avx2,fma"))) void radial_span_avx2_impl(const RadialArgs& a, uint32_t* out,
                                                               int x, int end, int half_offset) {
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
__attribute__((target("avx512f,avx512bw,avx512vbmi,avx2,fma"))) void radial_span_avx512_impl(
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

}  // namespace

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

int table_span_avx2(const uint8_t* base, int stride, const int32_t* pos, uint32_t* out, int x,
                    int end, int CX, int CY, int32_t sr, int32_t sb, int x_lo, int x_hi, int y_hi) {
  return table_span_avx2_impl(base, stride, pos, out, x, end, CX, CY, sr, sb, x_lo, x_hi, y_hi);
}

void radial_span_avx2(const RadialArgs& a, uint32_t* out, int x, int end, int half_offset,
                      bool clamp) {
  (clamp ? radial_span_avx2_impl<true> : radial_span_avx2_impl<false>)(a, out, x, end, half_offset);
}

void radial_span_avx512(const RadialArgs& a, uint32_t* out, int x, int end, int half_offset,
                        bool clamp) {
  (clamp ? radial_span_avx512_impl<true> : radial_span_avx512_impl<false>)(a, out, x, end,
                                                                           half_offset);
}

}  // namespace hd::render::lens::kernels
#endif
