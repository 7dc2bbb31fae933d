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

bool cpu_has_avx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}
#endif

bool sizes_fit(const LensWarp& w, const ImageRgba8& eyes, const ImageRgba8& panel) {
  return eyes.width >= 2 * w.eye_width() && eyes.height >= w.eye_height() &&
         panel.width == w.panel_width() && panel.height == w.panel_height() &&
         eyes.data.size() >= static_cast<std::size_t>(eyes.stride_bytes) * eyes.height &&
         panel.data.size() >= static_cast<std::size_t>(panel.stride_bytes) * panel.height;
}

}  // namespace

CpuPredistorter::CpuPredistorter(const LensWarp& warp, int threads, bool simd)
    : warp_(warp), threads_(std::clamp(threads, 1, 2)) {
#if HD_LENS_AVX2
  simd_ = simd && cpu_has_avx2();
#else
  (void)simd;
#endif
  const int pw = warp_.panel_width(), ph = warp_.panel_height(), hw = warp_.eye_panel_width();
  positions_.assign(static_cast<std::size_t>(pw) * ph * 2, 0);
  spans_.assign(static_cast<std::size_t>(ph) * 2, Span{});
  for (int c = 0; c < 3; ++c)
    scale_fixed_[c] = static_cast<int32_t>(std::lround(warp_.channel_scale(c) * 65536.0));
  for (int e = 0; e < 2; ++e) {
    centre_fixed_[e][0] =
        static_cast<int32_t>(std::lround((warp_.eye(e).cx + e * warp_.eye_width() - 0.5) * 256.0));
    centre_fixed_[e][1] = static_cast<int32_t>(std::lround((warp_.eye(e).cy - 0.5) * 256.0));
  }
  for (int y = 0; y < ph; ++y) {
    for (int e = 0; e < 2; ++e) {
      Span& s = spans_[static_cast<std::size_t>(y) * 2 + e];
      s.begin = s.end = e * hw;
      bool open = false;
      for (int x = 0; x < hw; ++x) {
        double u = 0.0, v = 0.0;
        if (!warp_.source(e, x + 0.5, y + 0.5, 1, &u, &v)) continue;
        const std::size_t i = (static_cast<std::size_t>(y) * pw + e * hw + x) * 2;
        positions_[i] = static_cast<int32_t>(std::floor((u + e * warp_.eye_width() - 0.5) * 256.0));
        positions_[i + 1] = static_cast<int32_t>(std::floor((v - 0.5) * 256.0));
        // The usable region is a disc cut by the half: one span per row.
        if (!open) s.begin = e * hw + x;
        open = true;
        s.end = e * hw + x + 1;
      }
    }
  }
  if (threads_ == 2) worker_ = std::thread([this] { worker_loop(); });
}

CpuPredistorter::~CpuPredistorter() {
  if (worker_.joinable()) {
    quit_.store(true);
    job_.fetch_add(1);
    job_.notify_one();
    worker_.join();
  }
}

void CpuPredistorter::worker_loop() {
  uint64_t seen = 0;
  for (;;) {
    job_.wait(seen);
    seen = job_.load();
    if (quit_.load()) return;
    band(worker_row_begin_, worker_row_end_);
    done_.store(seen);
    done_.notify_one();
  }
}

bool CpuPredistorter::apply(const ImageRgba8& eyes, ImageRgba8& panel) {
  if (!sizes_fit(warp_, eyes, panel)) return false;
  eyes_ = &eyes;
  panel_ = &panel;
  const int h = warp_.panel_height();
  if (threads_ == 2 && h >= 2) {
    worker_row_begin_ = h / 2;
    worker_row_end_ = h;
    const uint64_t my_job = job_.fetch_add(1) + 1;
    job_.notify_one();
    band(0, h / 2);
    for (uint64_t d = done_.load(); d != my_job; d = done_.load()) done_.wait(d);
  } else {
    band(0, h);
  }
  eyes_ = nullptr;
  panel_ = nullptr;
  return true;
}

void CpuPredistorter::band(int row_begin, int row_end) {
  const int pw = warp_.panel_width(), ew = warp_.eye_width();
  const int y_hi = warp_.eye_height() - 1;
  const uint8_t* base = eyes_->data.data();
  const int stride = eyes_->stride_bytes;
  const int64_t sr = scale_fixed_[0], sb = scale_fixed_[2];
  for (int y = row_begin; y < row_end; ++y) {
    uint32_t* out = reinterpret_cast<uint32_t*>(panel_->row(y));
    const int32_t* pos = positions_.data() + static_cast<std::size_t>(y) * pw * 2;
    int x = 0;
    for (int e = 0; e < 2; ++e) {
      const Span s = spans_[static_cast<std::size_t>(y) * 2 + e];
      const int x_lo = e * ew, x_hi = e * ew + ew - 1;
      const int CX = centre_fixed_[e][0], CY = centre_fixed_[e][1];
      for (; x < s.begin; ++x) out[x] = 0xFF000000u;  // opaque black (RGBA bytes 0, 0, 0, 255)
#if HD_LENS_AVX2
      if (simd_)
        x = span_avx2(base, stride, pos, out, x, s.end, CX, CY, scale_fixed_[0], scale_fixed_[2],
                      x_lo, x_hi, y_hi);
#endif
      for (; x < s.end; ++x) {
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
      const int half_end = (e + 1) * warp_.eye_panel_width();
      for (; x < half_end; ++x) out[x] = 0xFF000000u;
    }
  }
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
