#pragma once
// Mono8 (GenICam "Mono8", one byte of luminance per pixel) to the renderer's RGBA8.

#include <cstddef>
#include <cstdint>

namespace hd::drivers {

/// Converts one Mono8 image to RGBA8 as (v, v, v, 255). Pure: no allocation, no state.
///
/// Returns false and writes nothing when the input cannot be a valid frame: null pointers,
/// width/height <= 0, strides smaller than a row, or buffers shorter than the last row needs
/// (the last row needs only its own bytes, not a whole stride).
bool mono8_to_rgba(const uint8_t* src, std::size_t src_len, int width_px, int height_px,
                   int src_stride_bytes, uint8_t* dst, std::size_t dst_len, int dst_stride_bytes);

}  // namespace hd::drivers
