#pragma once
// Format negotiation as data (the approach libcamera takes with its configuration "validate"
// step): what the station asks a camera for, what the device answers it delivers, and the one
// rule that decides whether a calibration fits that answer.

#include <string>
#include <vector>

#include "drivers/frame.h"

namespace hd::drivers {

/// What the station asks of a camera at open: the calibration's size, the pixel formats it can
/// use (best first) and a rate. Zero or empty fields leave the driver's own configuration.
struct CameraFormatRequest {
  int width_px = 0;
  int height_px = 0;
  std::vector<PixelFormat> pixel_formats;  ///< as the device delivers them (before RGBA8)
  double frame_rate_hz = 0.0;
};

/// What a device delivers, read back from it. Trivially copyable: it travels inside a FormatEvent
/// through a lock-free ring.
struct CameraFormat {
  int width_px = 0;  ///< 0: not known yet (not opened, or a source that learns it from a frame)
  int height_px = 0;
  PixelFormat pixel_format = PixelFormat::kRgba8;  ///< on the wire, before conversion to RGBA8
  double frame_rate_hz = 0.0;                      ///< 0: the device does not say

  bool known() const { return width_px > 0 && height_px > 0; }
  /// Same image layout (size and pixel format); the rate is not part of it.
  bool same_image(const CameraFormat& o) const {
    return width_px == o.width_px && height_px == o.height_px && pixel_format == o.pixel_format;
  }
};

/// The device's answer to a CameraFormatRequest.
struct FormatNegotiation {
  CameraFormat delivered;
  std::string refused;  ///< what the device said when it did not take the request ("" if it did)
  std::string limits;   ///< what it can deliver instead (sizes, formats), for the operator
  std::string detail;   ///< settings beyond size, format and rate (region offset, binning)
};

/// The verdict of the negotiation rule on one answer.
struct FormatVerdict {
  bool ok = false;
  std::string problem;  ///< "" when ok; else names both sizes (or formats) and what the device said
};

/// The rule: the device must deliver exactly the requested width x height, in one of the
/// acceptable pixel formats when the request lists any. An integer multiple is not accepted: a
/// size alone cannot tell binning (which scales the calibration exactly: u' = u / k with pixel
/// centres at +0.5) from decimation (which also shifts it by (k - 1) / 2k px) or from a crop (which
/// does not scale it at all), so scaling p_c on a size match would be a guess. An unknown size
/// (a source that learns it from its first frame) passes; the camera pipeline then refuses every
/// frame of another size, and reports it as an event.
FormatVerdict judge_format(const CameraFormatRequest& wanted, const FormatNegotiation& got);

/// "640x480" / "640x480 Mono8 at 30 Hz" / "size unknown".
std::string size_text(int width_px, int height_px);
std::string format_text(const CameraFormat& f);

}  // namespace hd::drivers
