#pragma once
// RGB8 (GenICam "RGB8", packed R G B bytes per pixel) to the renderer's RGBA8.

#include <cstddef>
#include <cstdint>

namespace hd::drivers {

/// Converts one packed RGB8 image to RGBA8 with alpha 255. Pure: no allocation, no state.
///
/// Returns false and writes nothing when the input cannot be a valid frame (see mono8_to_rgba).
bool rgb8_to_rgba(const uint8_t* src, std::size_t src_len, int width_px, int height_px,
                  int src_stride_bytes, uint8_t* dst, std::size_t dst_len, int dst_stride_bytes);

}  // namespace hd::drivers
