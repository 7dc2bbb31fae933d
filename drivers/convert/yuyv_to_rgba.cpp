#include "drivers/convert/yuyv_to_rgba.h"

#include <array>
#include <bit>
#include <cstring>

namespace hd::drivers {
namespace {

// BT.601 limited range (Y in [16,235], Cb/Cr in [16,240]) coefficients scaled by 256:
// 1.164 -> 298, 1.596 -> 409, 0.391 -> 100, 0.813 -> 208, 2.018 -> 516.
// Every (sum >> 8) lies in [-278, 535] for 8-bit inputs: a table saturates it to [0, 255] without
// branches, which is what makes this loop fast (the clamps dominated).
static_assert(std::endian::native == std::endian::little, "RGBA packing assumes little-endian");
constexpr int kClipOffset = 320;
constexpr int kClipSize = 1024;
constexpr std::array<uint8_t, kClipSize> make_clip() {
  std::array<uint8_t, kClipSize> t{};
  for (int i = 0; i < kClipSize; ++i) {
    const int v = i - kClipOffset;
    t[static_cast<std::size_t>(i)] = static_cast<uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
  }
  return t;
}
constexpr std::array<uint8_t, kClipSize> kClip = make_clip();

inline void put_pixel(uint8_t* out, int c, int r_term, int g_term, int b_term) {
  const int y = 298 * c + 128 + (kClipOffset << 8);  // +128 rounds the >> 8 to nearest
  // One 32-bit store per pixel (RGBA in memory order on a little-endian host).
  const uint32_t px = uint32_t{kClip[static_cast<std::size_t>((y + r_term) >> 8)]} |
                      uint32_t{kClip[static_cast<std::size_t>((y + g_term) >> 8)]} << 8 |
                      uint32_t{kClip[static_cast<std::size_t>((y + b_term) >> 8)]} << 16 |
                      0xFF000000u;
  std::memcpy(out, &px, sizeof(px));
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
