#pragma once
// The size check every packed-pixel converter makes before it touches a buffer.

#include <cstddef>

namespace hd::drivers {

/// True when a buffer of `len` bytes holds `height_px` rows of `row_bytes` at `stride_bytes`.
/// The last row needs only its own bytes: drivers size buffers as stride * (h - 1) + row.
/// Callers check height_px > 0 first.
inline bool plane_fits(std::size_t len, int height_px, int stride_bytes, int row_bytes) {
  if (stride_bytes < row_bytes) return false;
  const auto need =
      static_cast<std::size_t>(stride_bytes) * static_cast<std::size_t>(height_px - 1) +
      static_cast<std::size_t>(row_bytes);
  return len >= need;
}

}  // namespace hd::drivers
