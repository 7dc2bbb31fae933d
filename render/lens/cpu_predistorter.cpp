#include "render/lens/cpu_predistorter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

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

bool sizes_fit(const LensWarp& w, const ImageRgba8& eyes, const ImageRgba8& panel) {
  return eyes.width >= 2 * w.eye_width() && eyes.height >= w.eye_height() &&
         panel.width == w.panel_width() && panel.height == w.panel_height() &&
         eyes.data.size() >= static_cast<std::size_t>(eyes.stride_bytes) * eyes.height &&
         panel.data.size() >= static_cast<std::size_t>(panel.stride_bytes) * panel.height;
}

}  // namespace

CpuPredistorter::CpuPredistorter(const LensWarp& warp, int threads)
    : warp_(warp), threads_(std::clamp(threads, 1, 2)) {
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
