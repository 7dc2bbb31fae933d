#include "drivers/convert/yuyv_to_rgba.h"

#include <algorithm>

namespace hd::drivers {
namespace {

// BT.601 limited range (Y in [16,235], Cb/Cr in [16,240]) coefficients scaled by 256:
// 1.164 -> 298, 1.596 -> 409, 0.391 -> 100, 0.813 -> 208, 2.018 -> 516.
inline uint8_t clamp_u8(int v) {
  return static_cast<uint8_t>(std::clamp(v, 0, 255));
}

inline void put_pixel(uint8_t* out, int c, int r_term, int g_term, int b_term) {
  const int y = 298 * c + 128;  // +128 rounds the >> 8 to nearest
  out[0] = clamp_u8((y + r_term) >> 8);
  out[1] = clamp_u8((y + g_term) >> 8);
  out[2] = clamp_u8((y + b_term) >> 8);
  out[3] = 255;
}

// Bytes an image needs when the last row is not padded to the full stride.
std::size_t required(int height_px, int stride_bytes, int row_bytes) {
  return static_cast<std::size_t>(height_px - 1) * static_cast<std::size_t>(stride_bytes) +
         static_cast<std::size_t>(row_bytes);
}

}  // namespace

std::size_t yuyv_required_bytes(int width_px, int height_px, int stride_bytes) {
  if (width_px <= 0 || height_px <= 0 || (width_px % 2) != 0) return 0;
  if (width_px > (1 << 16) || height_px > (1 << 16)) return 0;  // no overflow in row math
  const int row_bytes = width_px * 2;
  if (stride_bytes < row_bytes) return 0;
  return required(height_px, stride_bytes, row_bytes);
}

bool yuyv_to_rgba(const uint8_t* src, std::size_t src_len, int width_px, int height_px,
                  int src_stride_bytes, uint8_t* dst, std::size_t dst_len, int dst_stride_bytes) {
  if (src == nullptr || dst == nullptr) return false;
  const std::size_t need_src = yuyv_required_bytes(width_px, height_px, src_stride_bytes);
  if (need_src == 0 || src_len < need_src) return false;
  const int dst_row_bytes = width_px * 4;
  if (dst_stride_bytes < dst_row_bytes) return false;
  if (dst_len < required(height_px, dst_stride_bytes, dst_row_bytes)) return false;

  for (int row = 0; row < height_px; ++row) {
    const uint8_t* s =
        src + static_cast<std::size_t>(row) * static_cast<std::size_t>(src_stride_bytes);
    uint8_t* d = dst + static_cast<std::size_t>(row) * static_cast<std::size_t>(dst_stride_bytes);
    for (int x = 0; x < width_px; x += 2, s += 4, d += 8) {
      const int u = s[1] - 128;
      const int v = s[3] - 128;
      const int r_term = 409 * v;
      const int g_term = -100 * u - 208 * v;
      const int b_term = 516 * u;
      put_pixel(d, s[0] - 16, r_term, g_term, b_term);
      put_pixel(d + 4, s[2] - 16, r_term, g_term, b_term);
    }
  }
  return true;
}

}  // namespace hd::drivers
