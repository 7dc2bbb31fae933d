#include "render/lens/cpu_predistorter.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hd::render::lens {
namespace {

// One channel of the eye image at continuous (u, v) (pixel centres at +0.5), bilinear with
// 8-bit weights, clamped to the columns [x_lo, x_hi] and rows [0, y_hi] of the pixel's eye.
inline uint32_t sample(const uint8_t* base, int stride, float u, float v, int channel, int x_lo,
                       int x_hi, int y_hi) {
  const int xi = static_cast<int>(std::floor((u - 0.5f) * 256.0f));
  const int yi = static_cast<int>(std::floor((v - 0.5f) * 256.0f));
  const int fx = xi & 255, fy = yi & 255;
  const int x0 = std::clamp(xi >> 8, x_lo, x_hi), x1 = std::clamp((xi >> 8) + 1, x_lo, x_hi);
  const int y0 = std::clamp(yi >> 8, 0, y_hi), y1 = std::clamp((yi >> 8) + 1, 0, y_hi);
  const uint8_t* r0 = base + static_cast<std::ptrdiff_t>(y0) * stride + channel;
  const uint8_t* r1 = base + static_cast<std::ptrdiff_t>(y1) * stride + channel;
  const uint32_t top = r0[4 * x0] * (256 - fx) + r0[4 * x1] * fx;
  const uint32_t bottom = r1[4 * x0] * (256 - fx) + r1[4 * x1] * fx;
  return (top * static_cast<uint32_t>(256 - fy) + bottom * static_cast<uint32_t>(fy) + 32768) >> 16;
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
  offsets_.assign(static_cast<std::size_t>(pw) * ph * 2, 0.0f);
  spans_.assign(static_cast<std::size_t>(ph) * 2, Span{});
  for (int c = 0; c < 3; ++c) scale_[c] = static_cast<float>(warp_.channel_scale(c));
  for (int e = 0; e < 2; ++e) {
    cx_[e] = static_cast<float>(warp_.eye(e).cx + e * warp_.eye_width());
    cy_[e] = static_cast<float>(warp_.eye(e).cy);
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
        offsets_[i] = static_cast<float>(u - warp_.eye(e).cx);
        offsets_[i + 1] = static_cast<float>(v - warp_.eye(e).cy);
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
  const float sr = scale_[0], sb = scale_[2];
  for (int y = row_begin; y < row_end; ++y) {
    uint32_t* out = reinterpret_cast<uint32_t*>(panel_->row(y));
    const float* off = offsets_.data() + static_cast<std::size_t>(y) * pw * 2;
    int x = 0;
    for (int e = 0; e < 2; ++e) {
      const Span s = spans_[static_cast<std::size_t>(y) * 2 + e];
      const int x_lo = e * ew, x_hi = e * ew + ew - 1;
      const float cx = cx_[e], cy = cy_[e];
      for (; x < s.begin; ++x) out[x] = 0xFF000000u;  // opaque black (RGBA bytes 0, 0, 0, 255)
      for (; x < s.end; ++x) {
        const float du = off[2 * x], dv = off[2 * x + 1];
        const uint32_t r = sample(base, stride, cx + sr * du, cy + sr * dv, 0, x_lo, x_hi, y_hi);
        const uint32_t g = sample(base, stride, cx + du, cy + dv, 1, x_lo, x_hi, y_hi);
        const uint32_t b = sample(base, stride, cx + sb * du, cy + sb * dv, 2, x_lo, x_hi, y_hi);
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
          px |= sample(eyes.data.data(), eyes.stride_bytes, static_cast<float>(u + e * ew),
                       static_cast<float>(v), c, e * ew, e * ew + ew - 1, warp_.eye_height() - 1)
                << (8 * c);
        }
        out[e * hw + x] = px;
      }
    }
  }
  return true;
}

}  // namespace hd::render::lens
