#include "drivers/frame.h"

namespace hd::drivers {

std::string_view to_string(PixelFormat f) {
  switch (f) {
    case PixelFormat::kRgba8:
      return "RGBA8";
    case PixelFormat::kRgb8:
      return "RGB8";
    case PixelFormat::kMono8:
      return "Mono8";
    case PixelFormat::kYuyv:
      return "YUYV";
    case PixelFormat::kMjpeg:
      return "MJPEG";
    case PixelFormat::kBayerRggb8:
      return "BayerRG8";
    case PixelFormat::kBayerGrbg8:
      return "BayerGR8";
    case PixelFormat::kBayerGbrg8:
      return "BayerGB8";
    case PixelFormat::kBayerBggr8:
      return "BayerBG8";
  }
  return "unknown";
}

int bytes_per_pixel(PixelFormat f) {
  switch (f) {
    case PixelFormat::kRgba8:
      return 4;
    case PixelFormat::kRgb8:
      return 3;
    case PixelFormat::kYuyv:
      return 2;
    case PixelFormat::kMjpeg:
      return 0;
    default:
      return 1;
  }
}

}  // namespace hd::drivers
