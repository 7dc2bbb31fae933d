#include "render/lens/cpu_predistorter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/lens/lens_sampler.h"
#include "render/lens/predistort_kernels.h"

namespace hd::render::lens {
namespace {

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
      threads_(threads),
      rows_(threads_, RowWorker::Split::kClaimed, kRowsPerTake, /*spin=*/true) {
#if HD_LENS_AVX2
  if (simd != Simd::kNone && kernels::cpu_has_avx2()) simd_ = Simd::kAvx2;
  if (simd == Simd::kBest && method_ == Method::kRadial && kernels::cpu_has_avx512())
    simd_ = Simd::kAvx512;
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
          const kernels::RadialArgs a{eyes_->data.data(),
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
            kernels::radial_span_avx512(a, out, x, s.end, e * hw, !s.clamp_free);
          else
            kernels::radial_span_avx2(a, out, x, s.end, e * hw, !s.clamp_free);
          x = s.end;
        }
#endif
        radial_span_scalar(y, e, x, s.end, out);
      } else {
#if HD_LENS_AVX2
        if (simd_ != Simd::kNone) {
          const int32_t* pos =
              positions_.data() + static_cast<std::size_t>(y) * warp_.panel_width() * 2;
          x = kernels::table_span_avx2(eyes_->data.data(), eyes_->stride_bytes, pos, out, x, s.end,
                                       centre_fixed_[e][0], centre_fixed_[e][1], scale_fixed_[0],
                                       scale_fixed_[2], e * ew, e * ew + ew - 1,
                                       warp_.eye_height() - 1);
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
