#include "drivers/convert/mono8_to_rgba.h"

#include "drivers/convert/plane_span.h"

namespace hd::drivers {

bool mono8_to_rgba(const uint8_t* src, std::size_t src_len, int width_px, int height_px,
                   int src_stride_bytes, uint8_t* dst, std::size_t dst_len, int dst_stride_bytes) {
  if (src == nullptr || dst == nullptr || width_px <= 0 || height_px <= 0) return false;
  if (width_px > (1 << 28)) return false;  // 4 * width must not overflow int
  if (!plane_fits(src_len, height_px, src_stride_bytes, width_px)) return false;
  if (!plane_fits(dst_len, height_px, dst_stride_bytes, width_px * 4)) return false;
  for (int y = 0; y < height_px; ++y) {
    const uint8_t* s =
        src + static_cast<std::size_t>(y) * static_cast<std::size_t>(src_stride_bytes);
    uint8_t* d = dst + static_cast<std::size_t>(y) * static_cast<std::size_t>(dst_stride_bytes);
    for (int x = 0; x < width_px; ++x) {
      const uint8_t v = s[x];
      d[4 * x + 0] = v;
      d[4 * x + 1] = v;
      d[4 * x + 2] = v;
      d[4 * x + 3] = 255;
    }
  }
  return true;
}

}  // namespace hd::drivers
