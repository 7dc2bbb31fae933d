#pragma once
// One camera frame as the renderer consumes it.

#include <cstdint>
#include <string_view>
#include <vector>

#include "drivers/frame_calibration.h"

namespace hd::drivers {

/// Pixel layouts a device may deliver; converters turn each into kRgba8, the renderer's format
/// (RGBA8 uploads are several times cheaper than RGB on Mesa).
enum class PixelFormat : uint8_t {
  kRgba8,
  kRgb8,
  kMono8,
  kYuyv,
  kMjpeg,
  kBayerRggb8,
  kBayerGrbg8,
  kBayerGbrg8,
  kBayerBggr8
};

std::string_view to_string(PixelFormat f);
int bytes_per_pixel(PixelFormat f);  ///< 0 for compressed formats (MJPEG).

/// A frame in the renderer's format. `data` is sized once when the stream starts (width * height
/// * 4 bytes, or stride * height) and reused: filling a frame never allocates.
struct Frame {
  int width = 0;
  int height = 0;
  int stride_bytes = 0;  ///< bytes from one row to the next
  PixelFormat format = PixelFormat::kRgba8;
  uint64_t sequence = 0;            ///< device frame counter, unwrapped to 64 bits
  int64_t device_timestamp_ns = 0;  ///< the device's own clock (exposure), mapped if trusted
  int64_t host_timestamp_ns = 0;    ///< CLOCK_MONOTONIC: exposure if the device time is trusted,
                                    ///< else arrival
  bool device_time_trusted = false;
  /// A network camera's frame: when it crossed each stage of the link after its capture
  /// (host_timestamp_ns), CLOCK_MONOTONIC ns; 0 = not known (a local camera, a plain sender).
  struct LinkStages {
    int64_t encoded_ns = 0;   ///< the sender's encoder output
    int64_t sent_ns = 0;      ///< its last packet left the sender
    int64_t received_ns = 0;  ///< its packets arrived at the station
    int64_t decoded_ns = 0;   ///< the station's decoder output
  };
  LinkStages link;
  /// The calibration this frame was taken with, from the source (present only for a network
  /// camera whose sender streams it); else the station's calibration file applies.
  FrameCalibration calibration;
  std::vector<uint8_t> data;

  /// Allocates `data` for an RGBA8 image of this size (outside the per-frame path).
  void allocate_rgba(int w, int h) {
    width = w;
    height = h;
    stride_bytes = w * 4;
    format = PixelFormat::kRgba8;
    data.assign(static_cast<std::size_t>(stride_bytes) * static_cast<std::size_t>(h), 0);
  }
};

}  // namespace hd::drivers
