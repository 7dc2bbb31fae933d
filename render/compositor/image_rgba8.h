#pragma once
// An RGBA8 picture the compositors draw into (and textures they sample from).

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hd::render {

/// Row-major RGBA8, row 0 at the top (the same orientation as camera frames and the screen).
/// Pixel (x, y) covers the continuous square [x, x+1] x [y, y+1]; its centre is (x+0.5, y+0.5).
/// `data` is sized once by `allocate` (outside the per-frame path) and reused: drawing never
/// reallocates it.
struct ImageRgba8 {
  int width = 0;
  int height = 0;
  int stride_bytes = 0;  ///< bytes from one row to the next (>= 4 * width)
  std::vector<uint8_t> data;

  /// Sizes the buffer for w x h with tight rows and clears it to transparent black.
  void allocate(int w, int h) {
    width = w;
    height = h;
    stride_bytes = w * 4;
    data.assign(static_cast<std::size_t>(stride_bytes) * static_cast<std::size_t>(h), 0);
  }

  bool empty() const { return width <= 0 || height <= 0; }
  uint8_t* row(int y) { return data.data() + static_cast<std::ptrdiff_t>(y) * stride_bytes; }
  const uint8_t* row(int y) const {
    return data.data() + static_cast<std::ptrdiff_t>(y) * stride_bytes;
  }
  uint8_t* pixel(int x, int y) { return row(y) + 4 * x; }
  const uint8_t* pixel(int x, int y) const { return row(y) + 4 * x; }
};

}  // namespace hd::render
