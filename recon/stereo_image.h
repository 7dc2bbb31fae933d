#pragma once
// One camera's picture as the reconstruction takes it: pixels, their channel order, and when they
// were exposed.

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "drivers/frame.h"

namespace hd::recon {

/// kBgr: cv::imread's order (CV_8UC3); kRgba: drivers::Frame's kRgba8 (CV_8UC4); kGrey: CV_8UC1.
enum class ChannelOrder { kBgr, kRgba, kGrey };

struct StereoImage {
  cv::Mat pixels;  ///< empty = the frame is missing
  ChannelOrder order = ChannelOrder::kBgr;
  int64_t capture_ns = 0;  ///< CLOCK_MONOTONIC exposure time (drivers::Frame::host_timestamp_ns)

  /// Empty string if pixels match `order`, else what is wrong.
  std::string check() const;
};

/// Wraps an RGBA8 frame without copying (the frame must outlive the StereoImage and stay
/// unchanged while it is used). Another pixel format gives an empty (missing) image.
StereoImage stereo_image(const drivers::Frame& frame);

}  // namespace hd::recon
