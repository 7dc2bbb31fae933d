#pragma once
// Plain-language warnings when the numbers are poorly determined, though the RMS may look fine.

#include <string>
#include <vector>

#include "calib/coverage.h"
#include "calib/cross_validation.h"
#include "calib/intrinsics_calibration.h"

namespace hd::calib {

struct Warning {
  std::string code;     ///< stable id tests and tools can match: "principal_point", ...
  std::string message;  ///< what is wrong and what to do
};

/// Rules (thresholds relative to the image so they hold for any resolution):
/// - principal_point: sigma(cx) or sigma(cy) > 1% of the larger image side, or the principal point
///   is > 10% of the diagonal from the centre while the corners' hull covers < 60% of the image;
/// - distortion: a distortion term with sigma > max(|value|, 0.1) (e.g. k3 of a narrow set);
/// - coverage: < 50% of the 8x6 grid cells hold a corner;
/// - cross_validation: the two halves disagree by more than 1 px somewhere inside the area the
///   corners cover (outside it the models extrapolate; that figure is reported, not judged);
/// - few_views: fewer than 10 views;  outlier_views: a view flagged as outlier.
std::vector<Warning> quality_warnings(const IntrinsicsResult& r, const Coverage& c,
                                      const CrossValidation& xv);

}  // namespace hd::calib
