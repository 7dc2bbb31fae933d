#pragma once
// The stereo matcher: a rectified pair in, a full-resolution disparity map out (unknown = NaN).

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "recon/matcher_config.h"

namespace hd::recon {

/// Runs the configured OpenCV matcher on a rectified pair (CV_8UC1 or CV_8UC3 BGR, one size).
///
/// OpenCV leaves the left `max disparity` columns empty (their match would lie left of the right
/// image); the matcher pads both images on the left by that band (edge pixels repeated) so that
/// those columns are matched too, and crops the result.
///
/// Output: CV_32F, the input size, disparity in full-resolution pixels; NaN where the matcher
/// found nothing (OpenCV's invalid value, its uniqueness and left-right checks: SGBM always
/// cross-checks the left and right disparities from one cost volume, to at least 1 px). No
/// other filtering (disparity_filter.h does that). Buffers are reused between calls of equal
/// size.
class DisparityMatcher {
 public:
  /// Throws std::invalid_argument (MatcherConfig::check).
  explicit DisparityMatcher(const MatcherConfig& config);

  const MatcherConfig& config() const { return config_; }

  /// Throws std::invalid_argument for an empty pair, two sizes or an unsupported type.
  void compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity);

  /// The scale the matcher really works at (kSgbmScaled; 1 otherwise) and its coarse search
  /// range, for reports. Valid after compute().
  double effective_scale_x() const { return scale_x_; }
  int coarse_num_disparities() const { return coarse_num_; }

 private:
  void match_padded(cv::StereoMatcher& m, const cv::Mat& l, const cv::Mat& r, int pad,
                    cv::Mat& disparity16);

  MatcherConfig config_;
  cv::Ptr<cv::StereoSGBM> sgbm_;
  cv::Ptr<cv::StereoBM> bm_;
  int sgbm_cn_ = 0;
  int sgbm_min_ = 0, sgbm_num_ = 0;
  double scale_x_ = 1.0;
  int coarse_num_ = 0;
  cv::Mat l_, r_, l_small_, r_small_, l_pad_, r_pad_, disp16_, coarse_;
};

}  // namespace hd::recon
