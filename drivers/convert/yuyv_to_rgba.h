#pragma once
// YUYV 4:2:2 (V4L2_PIX_FMT_YUYV, the format every UVC webcam offers) to the renderer's RGBA8.

#include <cstddef>
#include <cstdint>

namespace hd::drivers {

/// Converts one YUYV image (Y0 U Y1 V per two pixels, BT.601 limited range, as UVC cameras send
/// it) to RGBA8 with alpha 255, in integer arithmetic (8-bit fixed point, within 1 of the exact
/// float formula). Pure: no allocation, no state.
///
/// Returns false and writes nothing when the input cannot be a valid frame: null pointers,
/// width/height <= 0, odd width (YUYV pairs pixels), strides smaller than a row, or buffers
/// shorter than the last row needs. `src_len`/`dst_len` are the bytes available; the last row
/// only needs its own bytes (not a whole stride), as drivers size buffers that way.
bool yuyv_to_rgba(const uint8_t* src, std::size_t src_len, int width_px, int height_px,
                  int src_stride_bytes, uint8_t* dst, std::size_t dst_len, int dst_stride_bytes);

/// Bytes a YUYV image of this size occupies with this stride (0 when the arguments are invalid).
std::size_t yuyv_required_bytes(int width_px, int height_px, int stride_bytes);

}  // namespace hd::drivers
