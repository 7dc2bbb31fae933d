#pragma once
// How well the station's proxy m predicts what the operator would see, from every frame's m and
// the image errors of the same frame drawn as pure video and as pure model (`hybrid-station
// score`): the paper's open question about m_t, answered for an image metric (not a user study).
//
// Spearman's rank correlation between m and the pure video view's error (its MSE, i.e. PSNR
// negated: ranks are the same), with ties given their mean rank. The break-even m: the frames
// sorted by m in `bins` groups of equal count; where the mean PSNR of the pure video view falls
// below the pure model's, linearly between the two groups' mean m.

#include <cstddef>
#include <vector>

namespace hd::station {

struct MSample {
  double m = 0.0;
  double video_psnr_db = 0.0;      ///< the frame drawn as pure video
  double synthetic_psnr_db = 0.0;  ///< the frame drawn as pure model
};

struct MAgainstTruth {
  std::size_t samples = 0;  ///< frames with a finite m and both views scored
  /// Spearman's rho of m against the video view's error; NaN with fewer than 3 samples.
  double spearman = 0.0;
  /// NaN when the video view is better (or worse) in every group: no crossing in the range.
  double break_even_m = 0.0;
};

/// Samples with a non-finite value are left out.
MAgainstTruth m_against_truth(std::vector<MSample> samples, int bins = 10);

/// Spearman's rho of two equally long series (mean ranks for ties); NaN below 3 values or when
/// either series is constant.
double spearman_rho(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace hd::station
