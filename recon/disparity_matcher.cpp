#include "recon/disparity_matcher.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "recon/guided_upsampling.h"

namespace hd::recon {

namespace {

// OpenCV's fixed-point disparity: 4 fractional bits.
constexpr float kDispScale =
    1.0f / static_cast<float>(static_cast<int>(cv::StereoMatcher::DISP_SCALE));

int round_up_16(int n) {
  return (n + 15) / 16 * 16;
}

// OpenCV sample's smoothness penalties (stereo_match.cpp): P1 for +-1 px steps, P2 for jumps.
int sgbm_p1(int cn, int block) {
  return 8 * cn * block * block;
}
int sgbm_p2(int cn, int block) {
  return 32 * cn * block * block;
}

int default_block(MatcherKind k) {
  switch (k) {
    case MatcherKind::kSgbmScaled:
      return 1;  // measured on Aloe: the coarse pass keeps more detail with single pixels
    case MatcherKind::kSgbm:
      return 3;  // OpenCV's sample
    case MatcherKind::kBm:
      return 9;  // OpenCV's sample
  }
  return 3;
}

// Fixed-point disparity (min - 1 = invalid) -> float in `to_full` units, NaN = unknown.
void to_float(const cv::Mat& d16, int min_disparity, float to_full, cv::Mat& out) {
  out.create(d16.size(), CV_32FC1);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int invalid_below = min_disparity * static_cast<int>(cv::StereoMatcher::DISP_SCALE);
  for (int y = 0; y < d16.rows; ++y) {
    const int16_t* s = d16.ptr<int16_t>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < d16.cols; ++x)
      o[x] = s[x] < invalid_below ? nan : static_cast<float>(s[x]) * kDispScale * to_full;
  }
}

}  // namespace

DisparityMatcher::DisparityMatcher(const MatcherConfig& config) : config_(config) {
  config_.check();
  if (config_.block_size_px == 0) config_.block_size_px = default_block(config_.kind);
}

void DisparityMatcher::match_padded(cv::StereoMatcher& m, const cv::Mat& l, const cv::Mat& r,
                                    int pad, cv::Mat& disparity16) {
  cv::copyMakeBorder(l, l_pad_, 0, 0, pad, 0, cv::BORDER_REPLICATE);
  cv::copyMakeBorder(r, r_pad_, 0, 0, pad, 0, cv::BORDER_REPLICATE);
  m.compute(l_pad_, r_pad_, disp16_);
  disparity16 = disp16_.colRange(pad, disp16_.cols);
}

void DisparityMatcher::compute(const cv::Mat& left, const cv::Mat& right, cv::Mat& disparity) {
  if (left.empty() || right.empty()) throw std::invalid_argument("DisparityMatcher: empty image");
  if (left.size() != right.size() || left.type() != right.type())
    throw std::invalid_argument("DisparityMatcher: left and right differ in size or type");
  if (left.type() != CV_8UC1 && left.type() != CV_8UC3)
    throw std::invalid_argument("DisparityMatcher: expected CV_8UC1 or CV_8UC3 (BGR) images");

  const MatcherConfig& c = config_;
  const bool grey = left.channels() == 1 || !c.colour || c.kind == MatcherKind::kBm;
  if (grey && left.channels() == 3) {
    cv::cvtColor(left, l_, cv::COLOR_BGR2GRAY);
    cv::cvtColor(right, r_, cv::COLOR_BGR2GRAY);
  } else {
    l_ = left;
    r_ = right;
  }
  const int cn = l_.channels();

  // Every kind searches from disparity 0, whatever the configured minimum: a surface farther
  // than the range then finds its true (too small) disparity, which the filter drops, instead of
  // the best wrong one inside the range (measured: a textured wall at 20 m with a 0.58..7.5 m
  // range gave 16 % of the image confidently wrong depths when the search started at 8 px).
  if (c.kind == MatcherKind::kBm) {
    const int num = round_up_16(c.max_disparity_px());
    if (!bm_) bm_ = cv::StereoBM::create(num, c.block_size_px);
    bm_->setMinDisparity(0);
    bm_->setNumDisparities(num);
    bm_->setBlockSize(c.block_size_px);
    bm_->setPreFilterCap(31);
    bm_->setTextureThreshold(10);
    bm_->setUniquenessRatio(c.uniqueness_percent);
    bm_->setDisp12MaxDiff(1);
    bm_->setSpeckleWindowSize(0);  // disparity_filter removes speckles for every kind alike
    scale_x_ = 1.0;
    coarse_num_ = num;
    cv::Mat d16;
    match_padded(*bm_, l_, r_, num, d16);
    to_float(d16, 0, 1.0f, disparity);
    return;
  }

  // SGBM, either at full size or on the downscaled pair.
  const bool scaled = c.kind == MatcherKind::kSgbmScaled && c.scale < 1.0;
  cv::Size small = l_.size();
  if (scaled) {
    small = cv::Size(std::max(16, static_cast<int>(std::lround(l_.cols * c.scale))),
                     std::max(16, static_cast<int>(std::lround(l_.rows * c.scale))));
  }
  const double sx = static_cast<double>(l_.cols) / small.width;
  const double sy = static_cast<double>(l_.rows) / small.height;
  const int min_c = 0;
  const int max_c = static_cast<int>(std::ceil(c.max_disparity_px() / sx));
  const int num_c = round_up_16(std::max(16, max_c - min_c));
  if (!sgbm_ || sgbm_cn_ != cn || sgbm_min_ != min_c || sgbm_num_ != num_c) {
    const int b = c.block_size_px;
    sgbm_ = cv::StereoSGBM::create(min_c, num_c, b, sgbm_p1(cn, b), sgbm_p2(cn, b),
                                   /*disp12MaxDiff=*/1, /*preFilterCap=*/63, c.uniqueness_percent,
                                   /*speckleWindowSize=*/0,
                                   /*speckleRange=*/0, cv::StereoSGBM::MODE_SGBM_3WAY);
    sgbm_cn_ = cn;
    sgbm_min_ = min_c;
    sgbm_num_ = num_c;
  }
  scale_x_ = sx;
  coarse_num_ = num_c;
  cv::Mat d16;
  if (!scaled) {
    match_padded(*sgbm_, l_, r_, min_c + num_c, d16);
    to_float(d16, min_c, 1.0f, disparity);
    return;
  }
  cv::resize(l_, l_small_, small, 0, 0, cv::INTER_AREA);
  cv::resize(r_, r_small_, small, 0, 0, cv::INTER_AREA);
  match_padded(*sgbm_, l_small_, r_small_, min_c + num_c, d16);
  to_float(d16, min_c, 1.0f, coarse_);
  upsample_disparity(coarse_, l_small_, l_, sx, sy, disparity);
}

}  // namespace hd::recon
