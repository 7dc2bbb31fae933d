#pragma once
// 8-bit Bayer mosaics (GenICam BayerRG8 / BayerGR8 / BayerGB8 / BayerBG8) to the renderer's RGBA8.

#include <cstddef>
#include <cstdint>

#include "drivers/frame.h"

namespace hd::drivers {

/// Bilinear demosaic of one 8-bit Bayer image to RGBA8 with alpha 255. Pure: no allocation.
///
/// `pattern` names the colours of the top-left 2x2 block in GenICam order (kBayerRggb8 = R at
/// (0,0), G at (1,0) and (0,1), B at (1,1)); note OpenCV names the same mosaic by its second row
/// (its COLOR_BayerBG2RGB reads RGGB data). Missing colours are the rounded mean of the nearest 2
/// or 4 samples of that colour. Borders mirror the image about its edge pixel (reflect-101), which
/// keeps the mosaic's colour parity, so edge pixels are interpolated from real samples as well.
///
/// Returns false and writes nothing when `pattern` is not a Bayer format, width or height < 2
/// (no full 2x2 cell), pointers are null, strides are smaller than a row, or buffers are short.
bool bayer_to_rgba(PixelFormat pattern, const uint8_t* src, std::size_t src_len, int width_px,
                   int height_px, int src_stride_bytes, uint8_t* dst, std::size_t dst_len,
                   int dst_stride_bytes);

}  // namespace hd::drivers
