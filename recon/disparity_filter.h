#pragma once
// The rules that turn a matcher's disparity into one the reconstruction may trust: what it cannot
// vouch for becomes unknown (NaN), never zero and never infinity.

#include <opencv2/core.hpp>

#include "recon/matcher_config.h"

namespace hd::recon {

struct FilterConfig {
  /// Connected regions (4-neighbours whose disparity differs by at most speckle_range_px) of at
  /// most speckle_window_px pixels are dropped: small islands are typically mismatches.
  int speckle_window_px = 100;
  double speckle_range_px = 2.0;
  /// Pixels whose left-image neighbourhood (texture_window_px square, grey) has a standard
  /// deviation below min_texture_dn carry no information to match: unknown. The default is above
  /// a camera's usual sensor noise (1-2 DN), so a plain surface stays unknown instead of
  /// receiving the smoothness term's guess. 0 = off.
  double min_texture_dn = 3.0;
  int texture_window_px = 9;
  /// Disparities within this margin of the search range's far end are dropped: a surface nearer
  /// than the range allows has its true match beyond the end, and the matcher piles up there.
  double range_end_margin_px = 1.0;

  void check() const;  ///< throws std::invalid_argument naming the field
};

/// What each rule removed (pixels), and what is left.
struct FilterCounts {
  int unmatched = 0;     ///< unknown on arrival (matcher found nothing)
  int out_of_range = 0;  ///< below the minimum disparity (including <= 0) or at the range's end
  int textureless = 0;
  int speckles = 0;
  int known = 0;
};

/// Applies the rules in place to `disparity` (CV_32F, NaN = unknown, full-resolution pixels of the
/// rectified left image `left_grey`, CV_8UC1 of the same size). `range` is the matcher's search
/// range. Buffers in `scratch` are reused between calls.
struct FilterScratch {
  cv::Mat mean, sq_mean, grey_f, d16;
  cv::Mat speckle_buf;
};
FilterCounts filter_disparity(const cv::Mat& left_grey, const MatcherConfig& range,
                              const FilterConfig& config, cv::Mat& disparity,
                              FilterScratch& scratch);

}  // namespace hd::recon
