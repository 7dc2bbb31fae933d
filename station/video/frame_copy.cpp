#include "station/video/frame_copy.h"

#include <cstddef>
#include <cstring>

namespace hd::station {

bool is_rgba_frame(const drivers::Frame& f, int w, int h) {
  if (f.format != drivers::PixelFormat::kRgba8 || f.width != w || f.height != h || w <= 0 ||
      h <= 0 || f.stride_bytes < 4 * w) {
    return false;
  }
  return f.data.size() >= static_cast<std::size_t>(f.stride_bytes) * static_cast<std::size_t>(h);
}

void copy_frame_stamps(const drivers::Frame& src, drivers::Frame& dst) {
  dst.sequence = src.sequence;
  dst.device_timestamp_ns = src.device_timestamp_ns;
  dst.host_timestamp_ns = src.host_timestamp_ns;
  dst.device_time_trusted = src.device_time_trusted;
  dst.link = src.link;
  dst.calibration = src.calibration;
}

bool copy_frame(const drivers::Frame& src, drivers::Frame& dst) {
  if (!is_rgba_frame(src, dst.width, dst.height) || !is_rgba_frame(dst, src.width, src.height))
    return false;
  const std::size_t row_bytes = static_cast<std::size_t>(src.width) * 4;
  if (src.stride_bytes == dst.stride_bytes) {
    std::memcpy(dst.data.data(), src.data.data(),
                static_cast<std::size_t>(src.stride_bytes) * static_cast<std::size_t>(src.height));
  } else {
    for (int y = 0; y < src.height; ++y)
      std::memcpy(dst.data.data() + static_cast<std::ptrdiff_t>(y) * dst.stride_bytes,
                  src.data.data() + static_cast<std::ptrdiff_t>(y) * src.stride_bytes, row_bytes);
  }
  copy_frame_stamps(src, dst);
  return true;
}

}  // namespace hd::station
