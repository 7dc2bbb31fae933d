#include "drivers/convert/bayer_to_rgba.h"

#include <array>

#include "drivers/convert/plane_span.h"

namespace hd::drivers {

namespace {

enum Channel : uint8_t { kR = 0, kG = 1, kB = 2 };

// Colour of the 2x2 cell positions (x&1) + 2*(y&1), in GenICam naming (top-left first).
bool cell_colours(PixelFormat pattern, std::array<Channel, 4>& out) {
  switch (pattern) {
    case PixelFormat::kBayerRggb8:
      out = {kR, kG, kG, kB};
      return true;
    case PixelFormat::kBayerGrbg8:
      out = {kG, kR, kB, kG};
      return true;
    case PixelFormat::kBayerGbrg8:
      out = {kG, kB, kR, kG};
      return true;
    case PixelFormat::kBayerBggr8:
      out = {kB, kG, kG, kR};
      return true;
    default:
      return false;
  }
}

// Reflect-101 about the edge pixel: -1 -> 1, n -> n - 2. Keeps the index's parity, hence its
// colour.
inline int reflect(int i, int n) {
  if (i < 0) return -i;
  if (i >= n) return 2 * n - 2 - i;
  return i;
}

inline uint8_t avg2(int a, int b) {
  return static_cast<uint8_t>((a + b + 1) >> 1);
}
inline uint8_t avg4(int a, int b, int c, int d) {
  return static_cast<uint8_t>((a + b + c + d + 2) >> 2);
}

}  // namespace

bool bayer_to_rgba(PixelFormat pattern, const uint8_t* src, std::size_t src_len, int width_px,
                   int height_px, int src_stride_bytes, uint8_t* dst, std::size_t dst_len,
                   int dst_stride_bytes) {
  std::array<Channel, 4> colours{};
  if (!cell_colours(pattern, colours)) return false;
  if (src == nullptr || dst == nullptr || width_px < 2 || height_px < 2) return false;
  if (width_px > (1 << 28)) return false;  // 4 * width must not overflow int
  if (!plane_fits(src_len, height_px, src_stride_bytes, width_px)) return false;
  if (!plane_fits(dst_len, height_px, dst_stride_bytes, width_px * 4)) return false;

  const auto row = [&](int y) {
    return src + static_cast<std::size_t>(y) * static_cast<std::size_t>(src_stride_bytes);
  };
  for (int y = 0; y < height_px; ++y) {
    const uint8_t* up = row(reflect(y - 1, height_px));
    const uint8_t* mid = row(y);
    const uint8_t* down = row(reflect(y + 1, height_px));
    uint8_t* d = dst + static_cast<std::size_t>(y) * static_cast<std::size_t>(dst_stride_bytes);
    const int py = 2 * (y & 1);
    for (int x = 0; x < width_px; ++x) {
      const int xl = reflect(x - 1, width_px);
      const int xr = reflect(x + 1, width_px);
      const Channel own = colours[static_cast<std::size_t>(py + (x & 1))];
      std::array<uint8_t, 3> rgb{};
      rgb[own] = mid[x];
      if (own == kG) {
        // Green site: one chroma lies left/right, the other above/below.
        const Channel horizontal = colours[static_cast<std::size_t>(py + ((x + 1) & 1))];
        const Channel vertical = horizontal == kR ? kB : kR;
        rgb[horizontal] = avg2(mid[xl], mid[xr]);
        rgb[vertical] = avg2(up[x], down[x]);
      } else {
        // Red or blue site: green on the 4 sides, the other chroma on the 4 diagonals.
        const Channel other = own == kR ? kB : kR;
        rgb[kG] = avg4(mid[xl], mid[xr], up[x], down[x]);
        rgb[other] = avg4(up[xl], up[xr], down[xl], down[xr]);
      }
      d[4 * x + 0] = rgb[0];
      d[4 * x + 1] = rgb[1];
      d[4 * x + 2] = rgb[2];
      d[4 * x + 3] = 255;
    }
  }
  return true;
}

}  // namespace hd::drivers
