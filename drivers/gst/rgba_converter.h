#pragma once
// Colour conversion between a GStreamer video frame and an RGBA Frame's own memory, with
// GStreamer's converter (the code videoconvert runs, same matrices and chroma resampling), so a
// frame is converted once, where it is, and never copied: the remote site's RGBA camera frame
// straight into the encoder's I420 buffer, the station's decoded I420 straight into its mailbox.

#include <gst/video/video.h>

#include "drivers/frame.h"

namespace hd::drivers {

class RgbaConverter {
 public:
  /// `threads`: how many threads one conversion is split over (GstVideoConverter's own).
  explicit RgbaConverter(int threads = 1) : threads_(threads) {}
  ~RgbaConverter();
  RgbaConverter(const RgbaConverter&) = delete;
  RgbaConverter& operator=(const RgbaConverter&) = delete;

  /// `f` (RGBA8, any stride) into `out` (mapped for writing, any raw format GStreamer converts
  /// to). False when the sizes differ or `f` is not RGBA8.
  bool from_rgba(const Frame& f, GstVideoFrame* out);
  /// `in` (mapped for reading) into `f`'s data, which must be RGBA8 of in's size already. False
  /// when it is not.
  bool to_rgba(const GstVideoFrame* in, Frame& f);

  /// Converters built so far: one per change of either side's format (not per frame).
  int converters_built() const { return built_; }

 private:
  static bool describe(const Frame& f, const GstVideoInfo& other, GstVideoFrame& raw);
  bool convert(const GstVideoFrame* in, GstVideoFrame* out);

  GstVideoConverter* converter_ = nullptr;
  GstVideoInfo in_{}, out_{};
  int built_ = 0;
  int threads_ = 1;
};

}  // namespace hd::drivers
