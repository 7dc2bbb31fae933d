#include "render/compositor/depth_warp.h"

#include <algorithm>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace hd::render {

DepthWarp DepthWarp::make(const core::Pinhole& eye, const core::Pose& T_world_eye,
                          const core::Pinhole& real, const core::Pose& T_world_real) {
  DepthWarp w;
  if (!eye.valid() || !real.valid() || !T_world_eye.valid() || !T_world_real.valid()) return w;
  // X_real = R X_eye + t with X_eye = z_eye K_o^-1 p, so K_c X_real / z_eye = A p + b / z_eye.
  const core::Pose T_real_eye = T_world_real.inverse() * T_world_eye;
  Eigen::Matrix3d K_o_inv;
  K_o_inv << 1.0 / eye.fx, 0, -eye.cx / eye.fx, 0, 1.0 / eye.fy, -eye.cy / eye.fy, 0, 0, 1;
  Eigen::Matrix3d K_c;
  K_c << real.fx, 0, real.cx, 0, real.fy, real.cy, 0, 0, 1;
  w.A = K_c * T_real_eye.R * K_o_inv;
  w.b = K_c * T_real_eye.t;
  w.usable = w.A.allFinite() && w.b.allFinite();
  return w;
}

namespace {

// One pixel, in exactly the order the header gives (the AVX loop does the same IEEE operations).
inline void depth_pixel(const DepthRow& w, int x, const float* eye_iz, float* u, float* v, float* a,
                        float* real_iz) {
  const double px = x + 0.5;
  double iz = eye_iz[x];
  const bool model = iz > 0.0;
  if (!model) iz = w.q0 * px + w.bz;
  u[x] = v[x] = a[x] = real_iz[x] = 0.0f;
  if (!(iz > 0.0) || iz > w.inv_near) return;
  const double hw = w.a20 * px + w.cw + w.b2 * iz;
  if (!(hw > 0.0)) return;
  const double s = 1.0 / hw;
  const double uu = (w.a00 * px + w.cx + w.b0 * iz) * s;
  const double vv = (w.a10 * px + w.cy + w.b1 * iz) * s;
  if (!(uu >= 0.0 && vv >= 0.0 && uu <= w.width && vv <= w.height)) return;
  u[x] = static_cast<float>(uu);
  v[x] = static_cast<float>(vv);
  a[x] = w.weight;
  if (model && w.seen != nullptr) real_iz[x] = static_cast<float>(iz * s);
}

#if defined(__x86_64__)
// Each 64-bit mask lane is all ones or all zeros: its low halves are the float mask.
__attribute__((target("avx"))) inline __m128 narrow(__m256d m) {
  const __m256 m8 = _mm256_castpd_ps(m);
  return _mm_shuffle_ps(_mm256_castps256_ps128(m8), _mm256_extractf128_ps(m8, 1),
                        _MM_SHUFFLE(2, 0, 2, 0));
}

__attribute__((target("avx"))) void depth_warp_row_avx(const DepthRow& w, int n,
                                                       const float* eye_iz, float* u, float* v,
                                                       float* a, float* real_iz) {
  const __m256d a00 = _mm256_set1_pd(w.a00), a10 = _mm256_set1_pd(w.a10);
  const __m256d a20 = _mm256_set1_pd(w.a20), cx = _mm256_set1_pd(w.cx);
  const __m256d cy = _mm256_set1_pd(w.cy), cw = _mm256_set1_pd(w.cw);
  const __m256d b0 = _mm256_set1_pd(w.b0), b1 = _mm256_set1_pd(w.b1), b2 = _mm256_set1_pd(w.b2);
  const __m256d q0 = _mm256_set1_pd(w.q0), bz = _mm256_set1_pd(w.bz), one = _mm256_set1_pd(1.0);
  const __m256d zero = _mm256_setzero_pd(), inv_near = _mm256_set1_pd(w.inv_near);
  const __m256d width = _mm256_set1_pd(w.width), height = _mm256_set1_pd(w.height);
  const __m128 weight = _mm_set1_ps(w.weight);
  const __m256d seen_on = w.seen != nullptr ? _mm256_cmp_pd(zero, zero, _CMP_EQ_OQ) : zero;
  __m256d px = _mm256_setr_pd(0.5, 1.5, 2.5, 3.5);  // exact: steps of 4.0
  const __m256d step = _mm256_set1_pd(4.0);
  int x = 0;
  for (; x + 4 <= n; x += 4, px = _mm256_add_pd(px, step)) {
    const __m256d izm = _mm256_cvtps_pd(_mm_loadu_ps(eye_iz + x));
    const __m256d model = _mm256_cmp_pd(izm, zero, _CMP_GT_OQ);
    const __m256d iz = _mm256_blendv_pd(_mm256_add_pd(_mm256_mul_pd(q0, px), bz), izm, model);
    const __m256d hw =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a20, px), cw), _mm256_mul_pd(b2, iz));
    const __m256d s = _mm256_div_pd(one, hw);
    const __m256d uu = _mm256_mul_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a00, px), cx), _mm256_mul_pd(b0, iz)), s);
    const __m256d vv = _mm256_mul_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a10, px), cy), _mm256_mul_pd(b1, iz)), s);
    // Ordered predicates: false for NaN, as the scalar comparisons.
    __m256d in =
        _mm256_and_pd(_mm256_cmp_pd(iz, zero, _CMP_GT_OQ), _mm256_cmp_pd(iz, inv_near, _CMP_LE_OQ));
    in = _mm256_and_pd(in, _mm256_cmp_pd(hw, zero, _CMP_GT_OQ));
    in = _mm256_and_pd(in, _mm256_and_pd(_mm256_cmp_pd(uu, zero, _CMP_GE_OQ),
                                         _mm256_cmp_pd(uu, width, _CMP_LE_OQ)));
    in = _mm256_and_pd(in, _mm256_and_pd(_mm256_cmp_pd(vv, zero, _CMP_GE_OQ),
                                         _mm256_cmp_pd(vv, height, _CMP_LE_OQ)));
    const __m128 m = narrow(in);
    _mm_storeu_ps(u + x, _mm_and_ps(m, _mm256_cvtpd_ps(uu)));
    _mm_storeu_ps(v + x, _mm_and_ps(m, _mm256_cvtpd_ps(vv)));
    _mm_storeu_ps(a + x, _mm_and_ps(m, weight));
    const __m128 test = narrow(_mm256_and_pd(in, _mm256_and_pd(model, seen_on)));
    _mm_storeu_ps(real_iz + x, _mm_and_ps(test, _mm256_cvtpd_ps(_mm256_mul_pd(iz, s))));
  }
  for (; x < n; ++x) depth_pixel(w, x, eye_iz, u, v, a, real_iz);
}
#endif

}  // namespace

void depth_warp_row_scalar(const DepthRow& w, int n, const float* eye_iz, float* u, float* v,
                           float* a, float* real_iz) {
  for (int x = 0; x < n; ++x) depth_pixel(w, x, eye_iz, u, v, a, real_iz);
}

void depth_warp_row(const DepthRow& w, int n, const float* eye_iz, float* u, float* v, float* a,
                    float* real_iz) {
#if defined(__x86_64__)
  static const bool has_avx = __builtin_cpu_supports("avx");
  if (has_avx) {
    depth_warp_row_avx(w, n, eye_iz, u, v, a, real_iz);
    return;
  }
#endif
  depth_warp_row_scalar(w, n, eye_iz, u, v, a, real_iz);
}

void seen_test_row(const DepthRow& w, int x_begin, int x_end, const float* u, const float* v,
                   const float* real_iz, float* a) {
  for (int x = x_begin; x < x_end; ++x) {
    if (!(real_iz[x] > 0.0f)) continue;
    const int sx = std::min(static_cast<int>(u[x]), w.seen_width - 1);
    const int sy = std::min(static_cast<int>(v[x]), w.seen_height - 1);
    if (!seen_by_real(real_iz[x], w.seen[static_cast<long>(sy) * w.seen_width + sx])) a[x] = 0.0f;
  }
}

}  // namespace hd::render
