#pragma once
// The rules that turn a matcher's disparity into one the reconstruction may trust: what it cannot
// vouch for becomes unknown (NaN), never zero and never infinity.

#include <opencv2/core.hpp>

#include "recon/matcher_config.h"

namespace hd::recon {

/// Defaults chosen on Middlebury's Aloe (real photographs) and on rendered hard cases
/// (tests/recon, docs/reconstruction.md has the figures): together they cost Aloe 0.3 % of
/// bad-2.0 (holes counted as bad) and remove nearly all geometry of a plain surface and of a
/// surface nearer or farther than the range.
struct FilterConfig {
  /// Connected regions (4-neighbours whose disparity differs by at most speckle_range_px) of at
  /// most speckle_window_px pixels are dropped: small islands are typically mismatches.
  int speckle_window_px = 300;
  double speckle_range_px = 2.0;
  /// Pixels whose left-image neighbourhood (texture_window_px square, grey) has a standard
  /// deviation below min_texture_dn are unknown. Off by default: the correlation test below
  /// already rejects flat windows (their correlation is undefined, counted as 0), and a fixed
  /// grey-level floor cost Aloe 0.6 % (2 DN) to 1.7 % (3 DN) of correct pixels.
  double min_texture_dn = 0.0;
  int texture_window_px = 9;
  /// Disparities within this margin of the search range's far end are dropped: a surface nearer
  /// than the range allows has its true match beyond the end, and the matcher piles up there.
  double range_end_margin_px = 1.0;
  /// Photo-consistency: the zero-mean normalised cross-correlation (ZNCC) of each left
  /// neighbourhood (correlation_window_px square, grey) with the right image at the matched
  /// disparity, averaged over the known pixels of a correlation_region_px square, must be at
  /// least min_correlation. A surface outside the search range, or one without texture, still
  /// gets a "best" disparity from the matcher's smoothness term; its patches do not correlate
  /// there as a whole. The regional mean keeps correct matches whose own window straddles a depth
  /// edge (a band a few pixels wide). -1 = off.
  double min_correlation = 0.4;
  int correlation_window_px = 7;
  int correlation_region_px = 15;

  void check() const;  ///< throws std::invalid_argument naming the field
};

/// What each rule removed (pixels), and what is left.
struct FilterCounts {
  int unmatched = 0;     ///< unknown on arrival (matcher found nothing)
  int out_of_range = 0;  ///< below the minimum disparity (including <= 0) or at the range's end
  int textureless = 0;
  int uncorrelated = 0;  ///< failed the photo-consistency check
  int speckles = 0;
  int known = 0;
};

/// Applies the rules in place to `disparity` (CV_32F, NaN = unknown, full-resolution pixels of the
/// rectified left image `left_grey`; `right_grey` the rectified right image, both CV_8UC1 of the
/// disparity's size). `range` is the matcher's search range. Buffers in `scratch` are reused.
struct FilterScratch {
  cv::Mat mean, sq_mean, grey_f, d16, map_x, map_y, warped, w_mean, w_sq, cross, prod, zncc, zknown;
  cv::Mat speckle_buf;
};
FilterCounts filter_disparity(const cv::Mat& left_grey, const cv::Mat& right_grey,
                              const MatcherConfig& range, const FilterConfig& config,
                              cv::Mat& disparity, FilterScratch& scratch);

}  // namespace hd::recon
