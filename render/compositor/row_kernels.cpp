#include "render/compositor/row_kernels.h"

#include <algorithm>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

// Both versions must stay bit-identical (tests/render/compositor_row_kernels_test.cpp): the SSE2
// loops do the very same IEEE operations in the same order, lane by lane. A contracted
// multiply-add (FMA) in the scalar loop would break that, so this file must not be built with
// -ffp-contract=fast on an FMA target; x86-64's baseline has no FMA.

namespace hd::render {

namespace {

inline void warp_pixel(const RowWarp& w, int x, float* u, float* v, float* a) {
  const double px = x + 0.5;
  const double iz = w.q0 * px + w.bz;
  const double s = 1.0 / (w.h20 * px + w.bw);
  const double uu = (w.h00 * px + w.bx) * s;
  const double vv = (w.h10 * px + w.by) * s;
  const bool in =
      iz > 0.0 && iz <= w.inv_near && uu >= 0.0 && uu <= w.width && vv >= 0.0 && vv <= w.height;
  u[x] = in ? static_cast<float>(uu) : 0.0f;
  v[x] = in ? static_cast<float>(vv) : 0.0f;
  a[x] = in ? w.weight : 0.0f;
}

inline uint8_t round_channel(float s, float a, float v) {
  const float val = s + a * (v - s);
  return static_cast<uint8_t>(std::clamp(val, 0.0f, 255.0f) + 0.5f);
}

inline void blend_pixel(const RowBlend& b, int x0, int x, const uint8_t* synth, const float* depth,
                        const float* a, const uint32_t* video, uint8_t* out) {
  uint32_t sp = b.background;
  if (depth[x] > 0.0f) std::memcpy(&sp, synth + 4 * x, 4);
  float s[3];
  for (int c = 0; c < 3; ++c) s[c] = static_cast<float>((sp >> (8 * c)) & 255u);
  if (b.desaturate) {
    const float grey = 0.299f * s[0] + 0.587f * s[1] + 0.114f * s[2];
    for (int c = 0; c < 3; ++c) s[c] += b.desaturation * (grey - s[c]);
  } else if (b.checker) {
    const float step =
        (((x0 + x) / b.checker_cell_px + b.checker_row) & 1) ? -b.checker_step : b.checker_step;
    for (int c = 0; c < 3; ++c) s[c] = std::clamp(s[c] + step, 0.0f, 255.0f);
  }
  if (b.fade > 0.0f)
    for (int c = 0; c < 3; ++c) s[c] += b.fade * (128.0f - s[c]);
  const float av = a ? a[x] : 0.0f;
  uint8_t* o = out + 4 * x;
  for (int c = 0; c < 3; ++c) {
    o[c] = round_channel(s[c], av, static_cast<float>((video[x] >> (8 * c)) & 255u));
  }
  o[3] = 255;
}

}  // namespace

void warp_row_scalar(const RowWarp& w, int n, float* u, float* v, float* a) {
  for (int x = 0; x < n; ++x) warp_pixel(w, x, u, v, a);
}

void blend_row_scalar(const RowBlend& b, int x0, int n, const uint8_t* synth, const float* depth,
                      const float* a, const uint32_t* video, uint8_t* out) {
  for (int x = 0; x < n; ++x) blend_pixel(b, x0, x, synth, depth, a, video, out);
}

#if defined(__SSE2__)

void warp_row_sse2(const RowWarp& w, int n, float* u, float* v, float* a) {
  const __m128d h00 = _mm_set1_pd(w.h00), h10 = _mm_set1_pd(w.h10), h20 = _mm_set1_pd(w.h20);
  const __m128d q0 = _mm_set1_pd(w.q0), bx = _mm_set1_pd(w.bx), by = _mm_set1_pd(w.by);
  const __m128d bw = _mm_set1_pd(w.bw), bz = _mm_set1_pd(w.bz), one = _mm_set1_pd(1.0);
  const __m128d zero = _mm_setzero_pd(), inv_near = _mm_set1_pd(w.inv_near);
  const __m128d width = _mm_set1_pd(w.width), height = _mm_set1_pd(w.height);
  const __m128 weight = _mm_set1_ps(w.weight);
  const __m128d half = _mm_set1_pd(0.5);
  // Two pixels per double vector, two vectors per step so that four floats are stored at once.
  auto pair = [&](int x, __m128& uf, __m128& vf, __m128& in_f) {
    const __m128d px = _mm_add_pd(_mm_cvtepi32_pd(_mm_setr_epi32(x, x + 1, 0, 0)), half);
    const __m128d iz = _mm_add_pd(_mm_mul_pd(q0, px), bz);
    const __m128d s = _mm_div_pd(one, _mm_add_pd(_mm_mul_pd(h20, px), bw));
    const __m128d uu = _mm_mul_pd(_mm_add_pd(_mm_mul_pd(h00, px), bx), s);
    const __m128d vv = _mm_mul_pd(_mm_add_pd(_mm_mul_pd(h10, px), by), s);
    __m128d in = _mm_and_pd(_mm_cmpgt_pd(iz, zero), _mm_cmple_pd(iz, inv_near));
    in = _mm_and_pd(in, _mm_and_pd(_mm_cmpge_pd(uu, zero), _mm_cmple_pd(uu, width)));
    in = _mm_and_pd(in, _mm_and_pd(_mm_cmpge_pd(vv, zero), _mm_cmple_pd(vv, height)));
    uf = _mm_cvtpd_ps(uu);  // round to nearest, as static_cast<float>
    vf = _mm_cvtpd_ps(vv);
    // Each 64-bit mask lane is all ones or all zeros: its low halves are the float mask.
    const __m128 m = _mm_castpd_ps(in);
    in_f = _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 0, 2, 0));
  };
  int x = 0;
  for (; x + 4 <= n; x += 4) {
    __m128 u0, v0, m0, u1, v1, m1;
    pair(x, u0, v0, m0);
    pair(x + 2, u1, v1, m1);
    const __m128 m = _mm_movelh_ps(m0, m1);
    _mm_storeu_ps(u + x, _mm_and_ps(m, _mm_movelh_ps(u0, u1)));
    _mm_storeu_ps(v + x, _mm_and_ps(m, _mm_movelh_ps(v0, v1)));
    _mm_storeu_ps(a + x, _mm_and_ps(m, weight));
  }
  for (; x < n; ++x) warp_pixel(w, x, u, v, a);
}

#if defined(__x86_64__) && defined(__GNUC__)

// Built for AVX whatever the file's flags (no FMA, so nothing is contracted); called only
// where the CPU has it. Four pixels per vector: half the SSE2 loop's instructions (it was
// instruction-bound: ~22 % of a video frame), the divisions cost the same per pixel.
__attribute__((target("avx"))) static void warp_row_avx_impl(const RowWarp& w, int n, float* u,
                                                             float* v, float* a) {
  const __m256d h00 = _mm256_set1_pd(w.h00), h10 = _mm256_set1_pd(w.h10);
  const __m256d h20 = _mm256_set1_pd(w.h20), q0 = _mm256_set1_pd(w.q0);
  const __m256d bx = _mm256_set1_pd(w.bx), by = _mm256_set1_pd(w.by);
  const __m256d bw = _mm256_set1_pd(w.bw), bz = _mm256_set1_pd(w.bz), one = _mm256_set1_pd(1.0);
  const __m256d zero = _mm256_setzero_pd(), inv_near = _mm256_set1_pd(w.inv_near);
  const __m256d width = _mm256_set1_pd(w.width), height = _mm256_set1_pd(w.height);
  const __m128 weight = _mm_set1_ps(w.weight);
  // x + 0.5 exactly: stepping by 4.0 stays exact far beyond any row length.
  __m256d px = _mm256_setr_pd(0.5, 1.5, 2.5, 3.5);
  const __m256d step = _mm256_set1_pd(4.0);
  int x = 0;
  for (; x + 4 <= n; x += 4, px = _mm256_add_pd(px, step)) {
    const __m256d iz = _mm256_add_pd(_mm256_mul_pd(q0, px), bz);
    const __m256d s = _mm256_div_pd(one, _mm256_add_pd(_mm256_mul_pd(h20, px), bw));
    const __m256d uu = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(h00, px), bx), s);
    const __m256d vv = _mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(h10, px), by), s);
    // Ordered predicates: false for NaN, as the scalar comparisons.
    __m256d in =
        _mm256_and_pd(_mm256_cmp_pd(iz, zero, _CMP_GT_OQ), _mm256_cmp_pd(iz, inv_near, _CMP_LE_OQ));
    in = _mm256_and_pd(in, _mm256_and_pd(_mm256_cmp_pd(uu, zero, _CMP_GE_OQ),
                                         _mm256_cmp_pd(uu, width, _CMP_LE_OQ)));
    in = _mm256_and_pd(in, _mm256_and_pd(_mm256_cmp_pd(vv, zero, _CMP_GE_OQ),
                                         _mm256_cmp_pd(vv, height, _CMP_LE_OQ)));
    // Each 64-bit mask lane is all ones or all zeros: its low halves are the float mask.
    const __m256 m8 = _mm256_castpd_ps(in);
    const __m128 m = _mm_shuffle_ps(_mm256_castps256_ps128(m8), _mm256_extractf128_ps(m8, 1),
                                    _MM_SHUFFLE(2, 0, 2, 0));
    _mm_storeu_ps(u + x, _mm_and_ps(m, _mm256_cvtpd_ps(uu)));  // round to nearest
    _mm_storeu_ps(v + x, _mm_and_ps(m, _mm256_cvtpd_ps(vv)));
    _mm_storeu_ps(a + x, _mm_and_ps(m, weight));
  }
  for (; x < n; ++x) warp_pixel(w, x, u, v, a);
}

void warp_row_avx(const RowWarp& w, int n, float* u, float* v, float* a) {
  static const bool has_avx = __builtin_cpu_supports("avx");
  if (has_avx) {
    warp_row_avx_impl(w, n, u, v, a);
  } else {
    warp_row_sse2(w, n, u, v, a);
  }
}

#else

void warp_row_avx(const RowWarp& w, int n, float* u, float* v, float* a) {
  warp_row_sse2(w, n, u, v, a);
}

#endif

void warp_row(const RowWarp& w, int n, float* u, float* v, float* a) {
  warp_row_avx(w, n, u, v, a);
}

void blend_row_sse2(const RowBlend& b, int x0, int n, const uint8_t* synth, const float* depth,
                    const float* a, const uint32_t* video, uint8_t* out) {
  const __m128i byte = _mm_set1_epi32(255), alpha = _mm_set1_epi32(static_cast<int>(0xFF000000u));
  const __m128i bg = _mm_set1_epi32(static_cast<int>(b.background));
  const __m128 zero = _mm_setzero_ps(), top = _mm_set1_ps(255.0f), half = _mm_set1_ps(0.5f);
  const __m128 one = _mm_set1_ps(1.0f);
  const __m128 kr = _mm_set1_ps(0.299f), kg = _mm_set1_ps(0.587f), kb = _mm_set1_ps(0.114f);
  const __m128 desat = _mm_set1_ps(b.desaturation);
  const int cell = b.checker_cell_px;
  auto channel = [&](__m128i p, int c) {
    return _mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(p, 8 * c), byte));
  };
  int x = 0;
  for (; x + 4 <= n; x += 4) {
    const __m128 av = a ? _mm_loadu_ps(a + x) : zero;
    const __m128i vp = _mm_loadu_si128(reinterpret_cast<const __m128i*>(video + x));
    if (_mm_movemask_ps(_mm_cmpeq_ps(av, one)) == 15) {
      // Pure video (most of a full-weight warp): s + 1 (v - s) rounds back to v exactly for
      // any s in [0, 255]: the float sum errs by under 1e-4, far inside the 0.5 rounding margin.
      _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 4 * static_cast<long>(x)),
                       _mm_or_si128(vp, alpha));
      continue;
    }
    const __m128i covered = _mm_castps_si128(_mm_cmpgt_ps(_mm_loadu_ps(depth + x), zero));
    const __m128i sp =
        _mm_or_si128(_mm_and_si128(covered, _mm_loadu_si128(reinterpret_cast<const __m128i*>(
                                                synth + 4 * static_cast<long>(x)))),
                     _mm_andnot_si128(covered, bg));
    __m128 s[3] = {channel(sp, 0), channel(sp, 1), channel(sp, 2)};
    if (b.desaturate) {
      const __m128 grey =
          _mm_add_ps(_mm_add_ps(_mm_mul_ps(kr, s[0]), _mm_mul_ps(kg, s[1])), _mm_mul_ps(kb, s[2]));
      for (auto& sc : s) sc = _mm_add_ps(sc, _mm_mul_ps(desat, _mm_sub_ps(grey, sc)));
    } else if (b.checker) {
      float st[4];
      for (int i = 0; i < 4; ++i) {
        st[i] = (((x0 + x + i) / cell + b.checker_row) & 1) ? -b.checker_step : b.checker_step;
      }
      const __m128 step = _mm_loadu_ps(st);
      for (auto& sc : s) sc = _mm_min_ps(_mm_max_ps(_mm_add_ps(sc, step), zero), top);
    }
    if (b.fade > 0.0f) {
      const __m128 fade = _mm_set1_ps(b.fade), mid = _mm_set1_ps(128.0f);
      for (auto& sc : s) sc = _mm_add_ps(sc, _mm_mul_ps(fade, _mm_sub_ps(mid, sc)));
    }
    __m128i o = alpha;
    for (int c = 0; c < 3; ++c) {
      const __m128 val = _mm_add_ps(s[c], _mm_mul_ps(av, _mm_sub_ps(channel(vp, c), s[c])));
      const __m128i r = _mm_cvttps_epi32(_mm_add_ps(_mm_min_ps(_mm_max_ps(val, zero), top), half));
      o = _mm_or_si128(o, _mm_slli_epi32(r, 8 * c));
    }
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 4 * static_cast<long>(x)), o);
  }
  for (; x < n; ++x) blend_pixel(b, x0, x, synth, depth, a, video, out);
}

#else

void warp_row_sse2(const RowWarp& w, int n, float* u, float* v, float* a) {
  warp_row_scalar(w, n, u, v, a);
}

void warp_row_avx(const RowWarp& w, int n, float* u, float* v, float* a) {
  warp_row_scalar(w, n, u, v, a);
}

void warp_row(const RowWarp& w, int n, float* u, float* v, float* a) {
  warp_row_scalar(w, n, u, v, a);
}

void blend_row_sse2(const RowBlend& b, int x0, int n, const uint8_t* synth, const float* depth,
                    const float* a, const uint32_t* video, uint8_t* out) {
  blend_row_scalar(b, x0, n, synth, depth, a, video, out);
}

#endif

}  // namespace hd::render
