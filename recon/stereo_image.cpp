#include "recon/stereo_image.h"

namespace hd::recon {

std::string StereoImage::check() const {
  if (pixels.empty()) return "no image";
  const int want = order == ChannelOrder::kBgr    ? CV_8UC3
                   : order == ChannelOrder::kRgba ? CV_8UC4
                                                  : CV_8UC1;
  if (pixels.type() != want)
    return "expected " +
           std::string(order == ChannelOrder::kBgr    ? "8-bit BGR"
                       : order == ChannelOrder::kRgba ? "8-bit RGBA"
                                                      : "8-bit grey") +
           " pixels";
  return "";
}

StereoImage stereo_image(const drivers::Frame& frame) {
  StereoImage s;
  s.order = ChannelOrder::kRgba;
  s.capture_ns = frame.host_timestamp_ns;
  if (frame.format != drivers::PixelFormat::kRgba8 || frame.width <= 0 || frame.height <= 0 ||
      frame.stride_bytes < 4 * frame.width ||
      frame.data.size() <
          static_cast<std::size_t>(frame.stride_bytes) * static_cast<std::size_t>(frame.height))
    return s;
  // cv::Mat does not take const data; the reconstruction only reads it.
  s.pixels = cv::Mat(frame.height, frame.width, CV_8UC4, const_cast<uint8_t*>(frame.data.data()),
                     static_cast<std::size_t>(frame.stride_bytes));
  return s;
}

}  // namespace hd::recon
