#pragma once
// The continuous per-pixel video weight (core::continuous_pixel_weight, DESIGN 7) evaluated
// cheaply: the compositor needs it at every video pixel, and core's version (a call, divisions,
// hypot and sin per pixel) was ~20 ms of a 800x600 frame.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hd::render {

/// The shaping sinusoid of w2, s(t) = (sin((t - 1/2) pi) + 1) / 2 on t in [0, 1], as a table
/// with linear interpolation between kIntervals + 1 exact samples (built once, never per frame).
///
/// Error bound: linear interpolation of a C2 function on a step h errs by at most
/// h^2 / 8 * max|s''|, and s''(t) = -(pi^2 / 2) sin((t - 1/2) pi), so max|s''| = pi^2 / 2.
/// With h = 1/1024: 2^-20 / 8 * 4.935 = 5.9e-7, i.e. 1.5e-4 of one 8-bit level (255 * 5.9e-7),
/// far below the 0.5/255 the tests allow; float rounding of the table and of the lerp adds
/// about 1e-7. Checked once with a throw-away driver (2026-11-22): max error 6.5e-7 over 1e7
/// evenly spaced t, and BorderWeight vs core::continuous_pixel_weight 6.4e-7 over 2e6 random
/// (w_video, u, v) in a 1600x1200 frame. The compositor test (weights vs core's w2 within 0.5
/// levels) checks the whole in CI.
class SinusoidTable {
 public:
  static constexpr int kIntervals = 1024;

  /// s(t), t clamped to [0, 1].
  static float at(float t) {
    const std::array<float, kIntervals + 2>& s = table();
    const float x = std::clamp(t, 0.0f, 1.0f) * static_cast<float>(kIntervals);
    const int i = static_cast<int>(x);  // x >= 0: truncation is floor; t = 1 uses the pad entry
    const float f = x - static_cast<float>(i);
    return s[i] + f * (s[i + 1] - s[i]);
  }

  /// s(t) four at a time, t in [0, 1] or clamped: the same float operations as at().
#if defined(__SSE2__)
  static __m128 at4(__m128 t) {
    const float* s = table().data();
    const __m128 x = _mm_mul_ps(_mm_min_ps(_mm_max_ps(t, _mm_setzero_ps()), _mm_set1_ps(1.0f)),
                                _mm_set1_ps(static_cast<float>(kIntervals)));
    const __m128i i = _mm_cvttps_epi32(x);
    const __m128 f = _mm_sub_ps(x, _mm_cvtepi32_ps(i));
    alignas(16) int idx[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(idx), i);
    const __m128 s0 = _mm_setr_ps(s[idx[0]], s[idx[1]], s[idx[2]], s[idx[3]]);
    const __m128 s1 = _mm_setr_ps(s[idx[0] + 1], s[idx[1] + 1], s[idx[2] + 1], s[idx[3] + 1]);
    return _mm_add_ps(s0, _mm_mul_ps(f, _mm_sub_ps(s1, s0)));
  }
#endif

 private:
  static const std::array<float, kIntervals + 2>& table() {
    // Function-local static: filled once, thread-safe, no heap.
    static const std::array<float, kIntervals + 2> s = [] {
      std::array<float, kIntervals + 2> a{};
      for (int i = 0; i <= kIntervals; ++i) {
        const double t = static_cast<double>(i) / kIntervals;
        a[i] = static_cast<float>((std::sin((t - 0.5) * std::numbers::pi) + 1.0) / 2.0);
      }
      a[kIntervals + 1] = a[kIntervals];  // so t = 1 may read i + 1
      return a;
    }();
    return s;
  }
};

/// core::continuous_pixel_weight(w_video, u, v, width, height) with the per-frame constants
/// hoisted: w = strength * s(w'2) with strength = min(1, 2 w_video), border kappa' =
/// min(1, 2 (1 - w_video)), w'2 the linear ramp of DESIGN 6 (rounded corners) and s the
/// sinusoid above. Same clamping as core: x' = min(|1 - 2u/width|, 1), likewise y'.
class BorderWeight {
 public:
  /// w_video already clamped to [0, 1]; width, height > 0 (the frame size in pixels).
  BorderWeight(double w_video, double width, double height)
      : strength_(std::min(1.0, 2.0 * w_video)),
        kappa_(std::min(1.0, 2.0 * (1.0 - w_video))),
        inner_(1.0 - kappa_),
        inv_kappa_(kappa_ > 0.0 ? 1.0 / kappa_ : 0.0),
        two_over_w_(2.0 / width),
        two_over_h_(2.0 / height) {}

  double strength() const { return strength_; }

  /// The weight at real-image position (u, v) (continuous pixel coordinates).
  float operator()(double u, double v) const {
    if (kappa_ <= 0.0) return static_cast<float>(strength_);  // core: kappa = 0 -> w2 = 1
    const double x = std::min(std::abs(1.0 - u * two_over_w_), 1.0);
    const double y = std::min(std::abs(1.0 - v * two_over_h_), 1.0);
    const bool bx = x > inner_, by = y > inner_;
    if (!bx && !by) return static_cast<float>(strength_);
    double w;
    if (bx && by) {
      const double dx = x - inner_, dy = y - inner_;
      w = 1.0 - std::sqrt(dx * dx + dy * dy) * inv_kappa_;
    } else {
      w = (1.0 - (bx ? x : y)) * inv_kappa_;
    }
    return static_cast<float>(strength_) * SinusoidTable::at(static_cast<float>(w));
  }

  /// a[x] = (*this)(u[x], v[x]) wherever a[x] > 0, for x in [0, n), one pixel at a time.
  void apply_row_scalar(int n, const float* u, const float* v, float* a) const {
    for (int x = 0; x < n; ++x) {
      if (a[x] > 0.0f) a[x] = (*this)(u[x], v[x]);
    }
  }

  /// The same, four pixels at a time with SSE2 (the same double and float operations, lane by
  /// lane, so the same bits; tests/render/compositor_row_kernels_test.cpp).
  void apply_row(int n, const float* u, const float* v, float* a) const {
    int x = 0;
#if defined(__SSE2__)
    if (kappa_ > 0.0) {
      const __m128d one = _mm_set1_pd(1.0), inner = _mm_set1_pd(inner_);
      const __m128d inv_kappa = _mm_set1_pd(inv_kappa_);
      const __m128d sx = _mm_set1_pd(two_over_w_), sy = _mm_set1_pd(two_over_h_);
      const __m128d sign = _mm_set1_pd(-0.0);
      const __m128 strength = _mm_set1_ps(static_cast<float>(strength_));
      // w (as float) and "in the inner rectangle" for two pixels from their positions.
      auto pair = [&](__m128 uf, __m128 vf, __m128& w, __m128& flat) {
        const __m128d px =
            _mm_min_pd(_mm_andnot_pd(sign, _mm_sub_pd(one, _mm_mul_pd(_mm_cvtps_pd(uf), sx))), one);
        const __m128d py =
            _mm_min_pd(_mm_andnot_pd(sign, _mm_sub_pd(one, _mm_mul_pd(_mm_cvtps_pd(vf), sy))), one);
        const __m128d bx = _mm_cmpgt_pd(px, inner), by = _mm_cmpgt_pd(py, inner);
        const __m128d dx = _mm_sub_pd(px, inner), dy = _mm_sub_pd(py, inner);
        const __m128d corner = _mm_sub_pd(
            one,
            _mm_mul_pd(_mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy))), inv_kappa));
        const __m128d edge_pos = _mm_or_pd(_mm_and_pd(bx, px), _mm_andnot_pd(bx, py));
        const __m128d edge = _mm_mul_pd(_mm_sub_pd(one, edge_pos), inv_kappa);
        const __m128d both = _mm_and_pd(bx, by);
        const __m128d wd = _mm_or_pd(_mm_and_pd(both, corner), _mm_andnot_pd(both, edge));
        w = _mm_cvtpd_ps(wd);
        const __m128 f = _mm_castpd_ps(_mm_or_pd(bx, by));
        flat = _mm_shuffle_ps(f, f, _MM_SHUFFLE(2, 0, 2, 0));  // lanes 0, 1: "not flat"
      };
      for (; x + 4 <= n; x += 4) {
        const __m128 av = _mm_loadu_ps(a + x);
        const __m128 live = _mm_cmpgt_ps(av, _mm_setzero_ps());
        if (_mm_movemask_ps(live) == 0) continue;
        const __m128 uf = _mm_loadu_ps(u + x), vf = _mm_loadu_ps(v + x);
        __m128 w0, w1, b0, b1;
        pair(uf, vf, w0, b0);
        pair(_mm_movehl_ps(uf, uf), _mm_movehl_ps(vf, vf), w1, b1);
        const __m128 w = _mm_movelh_ps(w0, w1), border = _mm_movelh_ps(b0, b1);
        const __m128 shaped = _mm_mul_ps(strength, SinusoidTable::at4(w));
        const __m128 weight =
            _mm_or_ps(_mm_and_ps(border, shaped), _mm_andnot_ps(border, strength));
        _mm_storeu_ps(a + x, _mm_or_ps(_mm_and_ps(live, weight), _mm_andnot_ps(live, av)));
      }
    }
#endif
    apply_row_scalar(n - x, u + x, v + x, a + x);
  }

 private:
  double strength_, kappa_, inner_, inv_kappa_, two_over_w_, two_over_h_;
};

}  // namespace hd::render
