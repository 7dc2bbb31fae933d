#pragma once
// What the stereo matcher searches and how: the disparity range, the algorithm and its knobs.

#include <string>
#include <string_view>

namespace hd::recon {

/// kSgbmScaled (the station's default): OpenCV's StereoSGBM (3-way) on the pair downscaled by
/// `scale`, its disparity brought back to full resolution by guided upsampling (each full pixel
/// takes the bilinear value where the coarse neighbours agree, else the value of the neighbour
/// whose colour matches it best). On Middlebury's Aloe it is as accurate as full-resolution SGBM
/// in about half the time (docs/reconstruction.md, bench/recon).
/// kSgbm: StereoSGBM 3-way at full resolution. kBm: StereoBM (block matching) at full
/// resolution, grey; fast, with many holes.
enum class MatcherKind { kSgbmScaled, kSgbm, kBm };

std::string_view to_string(MatcherKind k);
/// "sgbm-scaled", "sgbm", "bm"; throws std::invalid_argument naming the accepted values.
MatcherKind matcher_kind_from_string(std::string_view s);

/// Disparities are in full-resolution rectified pixels, d = x_left - x_right > 0.
struct MatcherConfig {
  MatcherKind kind = MatcherKind::kSgbmScaled;
  /// The accepted range [min_disparity_px, min_disparity_px + num_disparities_px). The minimum
  /// must be >= 1: d = 0 is a point at infinity and never a measurement. The far end of the range
  /// (depth f B / min) and its near end (f B / max) bound where depth can be measured at all.
  /// The matcher itself searches from 0 to the maximum (rounded up to OpenCV's multiple of 16),
  /// so that surfaces beyond the far end match where they are and are then dropped.
  int min_disparity_px = 1;
  int num_disparities_px = 112;
  /// kSgbmScaled: the image scale the matcher works at (0.25..1). The coarse range is rounded up
  /// to OpenCV's multiple of 16, so 0.7 with 112 disparities searches 80 coarse ones.
  double scale = 0.7;
  /// Matching block edge (odd); 0 = the kind's default (1 scaled, 3 sgbm, 9 bm).
  int block_size_px = 0;
  /// Match colour (3 channels) rather than grey where the images have colour (SGBM kinds).
  bool colour = true;
  /// OpenCV's uniqueness margin (%): the best cost must beat the second best by this much.
  int uniqueness_percent = 10;

  /// Throws std::invalid_argument naming the field for an unusable value.
  void check() const;
  int max_disparity_px() const { return min_disparity_px + num_disparities_px; }
};

}  // namespace hd::recon
