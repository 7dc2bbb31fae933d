#include "drivers/camera_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hd::drivers {

std::string size_text(int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0) return "size unknown";
  return std::to_string(width_px) + "x" + std::to_string(height_px);
}

std::string format_text(const CameraFormat& f) {
  if (!f.known()) return "size unknown";
  std::string s = size_text(f.width_px, f.height_px) + " " + std::string(to_string(f.pixel_format));
  if (f.frame_rate_hz > 0.0 && std::isfinite(f.frame_rate_hz)) {
    char rate[32];
    std::snprintf(rate, sizeof rate, " at %.4g Hz", f.frame_rate_hz);
    s += rate;
  }
  return s;
}

FormatVerdict judge_format(const CameraFormatRequest& wanted, const FormatNegotiation& got) {
  const CameraFormat& d = got.delivered;
  if (!d.known()) return {true, ""};
  std::string why;
  const bool size_asked = wanted.width_px > 0 && wanted.height_px > 0;
  if (size_asked && (d.width_px != wanted.width_px || d.height_px != wanted.height_px)) {
    why = "delivers " + size_text(d.width_px, d.height_px) + ", not the requested " +
          size_text(wanted.width_px, wanted.height_px);
  } else if (!wanted.pixel_formats.empty() &&
             std::find(wanted.pixel_formats.begin(), wanted.pixel_formats.end(), d.pixel_format) ==
                 wanted.pixel_formats.end()) {
    why = "delivers " + std::string(to_string(d.pixel_format)) + ", not one of";
    for (PixelFormat f : wanted.pixel_formats) why += " " + std::string(to_string(f));
  }
  if (why.empty()) return {true, ""};
  if (!got.refused.empty()) why += " (" + got.refused + ")";
  if (!got.limits.empty()) why += "; it can deliver " + got.limits;
  return {false, why};
}

}  // namespace hd::drivers
