#pragma once
// Turns a distorted camera frame into the pinhole frame the compositors and the model expect.

#include <cstdint>
#include <vector>

#include "core/pinhole.h"
#include "drivers/frame.h"

namespace hd::station {

/// Undistorts RGBA8 frames of one camera onto its own pinhole p_c (same fx, fy, cx, cy, width,
/// height, no distortion): output pixel centre (x+0.5, y+0.5) shows what the lens imaged from
/// the ray p_c.ray(x+0.5, y+0.5).
///
/// The maps come from cv::initUndistortRectifyMap in OpenCV's fixed-point form (CV_16SC2
/// integer source pixel + CV_16UC1 index of the 1/32-pixel bilinear fraction), computed once.
/// apply() runs the fixed-point bilinear lookup itself with exactly cv::remap's INTER_LINEAR /
/// BORDER_CONSTANT(0) semantics (a test compares the two) because cv::remap allocates a
/// scratch Mat and a thread-pool job per call, and the per-frame path must not allocate.
/// Source samples outside the frame count as transparent black (as cv::remap's border).
/// Interior pixels run an SSE2 kernel with the same integer sums (bit-identical to the scalar
/// path and to cv::remap: docs/video-and-model.md).
class Undistorter {
 public:
  Undistorter() = default;
  /// Builds the maps for `p_c` (its `distortion` as calibrated). Throws std::invalid_argument
  /// naming the problem when p_c is not a valid pinhole.
  explicit Undistorter(const core::Pinhole& p_c);

  /// True when any of p_c's first `distortion_count` coefficients is non-zero (else a copy does).
  static bool needed(const core::Pinhole& p_c);

  /// Writes the undistorted `src` into `dst` (both RGBA8, p_c's size; `dst.data` already sized:
  /// nothing is allocated) and copies sequence and timestamps. Returns false, leaving `dst`
  /// untouched, when `src` or `dst` does not match (size, format, stride, buffer length).
  bool apply(const drivers::Frame& src, drivers::Frame& dst) const;

  /// Where output pixel centre (x+0.5, y+0.5) samples the source, in continuous source pixel
  /// coordinates (pixel centres at +0.5), as the fixed-point maps encode it (1/32 px steps).
  /// For tests and diagnostics.
  void source_of(int x, int y, double& u, double& v) const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<int16_t> map_xy_;  ///< per output pixel: integer source x, y (CV_16SC2)
  std::vector<uint16_t>
      map_frac_;  ///< per output pixel: fy * 32 + fx, fractions in 1/32 (CV_16UC1)
};

}  // namespace hd::station
