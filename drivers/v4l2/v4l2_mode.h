#pragma once
// What a V4L2 device can deliver (formats x sizes x frame intervals) as plain data, and the
// choice of one mode for a request: negotiation is a pure function over that data, testable
// without a device (the approach libcamera takes with its configuration "validate" step).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "drivers/frame.h"
#include "drivers/v4l2/v4l2_syscalls.h"

namespace hd::drivers {

/// Seconds per frame as V4L2 states it (numerator / denominator).
struct V4l2Interval {
  uint32_t numerator = 0;
  uint32_t denominator = 0;
  double fps() const { return numerator == 0 ? 0.0 : double(denominator) / double(numerator); }
  bool operator==(const V4l2Interval&) const = default;
};

/// One size of one pixel format, with the frame intervals the driver lists for it (empty when it
/// lists none: we then ask for the rate with S_PARM and take the answer).
struct V4l2Mode {
  uint32_t fourcc = 0;
  int width_px = 0;
  int height_px = 0;
  std::vector<V4l2Interval> intervals;
};

struct V4l2ModeRequest {
  int width_px = 640;
  int height_px = 480;
  double fps = 30.0;
  uint32_t fourcc = 0;  ///< 0: any format we can convert (YUYV preferred, then MJPEG)
};

struct V4l2ModeChoice {
  uint32_t fourcc = 0;
  int width_px = 0;
  int height_px = 0;
  V4l2Interval interval;  ///< {0,0} when the driver listed no intervals
};

/// True for the formats this driver converts to RGBA8: YUYV and MJPEG (and JPEG, its alias).
bool v4l2_fourcc_supported(uint32_t fourcc);
PixelFormat v4l2_pixel_format(uint32_t fourcc);  ///< kYuyv or kMjpeg; only for supported fourccs
std::string v4l2_fourcc_name(uint32_t fourcc);   ///< "YUYV", "MJPG", or the raw four characters

/// Best mode for the request, or nullopt when no mode has a supported format. Ranking, in order:
/// exact size; else the smallest size covering the request; else the largest smaller one; then a
/// rate reaching the requested fps, closest to it; then YUYV over MJPEG (no decode, no artefacts).
std::optional<V4l2ModeChoice> choose_v4l2_mode(const std::vector<V4l2Mode>& modes,
                                               const V4l2ModeRequest& request);

/// Lists every format (ENUM_FMT), size (ENUM_FRAMESIZES) and interval (ENUM_FRAMEINTERVALS) of an
/// open capture node. Stepwise/continuous sizes contribute the requested size clamped to their
/// range and snapped to their step; stepwise intervals contribute their two ends.
std::vector<V4l2Mode> enumerate_v4l2_modes(V4l2Syscalls& sys, int fd,
                                           const V4l2ModeRequest& request);

}  // namespace hd::drivers
