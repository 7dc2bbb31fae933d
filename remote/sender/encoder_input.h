#pragma once
// The encoder's input at the remote site: each RGBA camera frame converted once, straight into a
// reused buffer of the format the encoder takes (I420 for x264enc). Before, push() copied the
// frame into a freshly allocated RGBA buffer (a new 3.7 MB mapping per 1280x720 frame,
// page-faulted in by the copy) and a videoconvert element converted that copy.

#include <gst/gst.h>
#include <gst/video/video.h>

#include "drivers/frame.h"
#include "drivers/gst/rgba_converter.h"

namespace hd::remote {

class EncoderInput {
 public:
  EncoderInput() = default;
  ~EncoderInput();
  EncoderInput(const EncoderInput&) = delete;
  EncoderInput& operator=(const EncoderInput&) = delete;

  /// The format to convert to, from the caps the encoder is fed with (appsrc's). False when they
  /// are not fixed raw video or the buffer pool cannot start.
  bool configure(GstCaps* caps);
  /// A buffer of that format holding `f` (RGBA8 of the same size) converted; the caller owns it.
  /// nullptr when `f` does not fit. One thread at a time.
  GstBuffer* convert(const drivers::Frame& f);

 private:
  GstVideoInfo info_{};
  // Unbounded (max 0): appsrc's leaky queue never makes push() wait for a buffer to come back.
  GstBufferPool* pool_ = nullptr;
  drivers::RgbaConverter converter_;
};

}  // namespace hd::remote
