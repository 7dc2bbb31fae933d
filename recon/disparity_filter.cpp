#include "recon/disparity_filter.h"

#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace hd::recon {

namespace {
// Fixed point used for the speckle pass (cv::filterSpeckles works on integers).
constexpr float kSpeckleScale = 16.0f;
constexpr int16_t kSpeckleUnknown = -1;
}  // namespace

void FilterConfig::check() const {
  auto bad = [](const char* field, const char* what) {
    throw std::invalid_argument(std::string("filter.") + field + ": " + what);
  };
  if (speckle_window_px < 0) bad("speckle_window_px", "must be >= 0");
  if (!(speckle_range_px >= 0)) bad("speckle_range_px", "must be >= 0");
  if (!(min_texture_dn >= 0)) bad("min_texture_dn", "must be >= 0");
  if (texture_window_px < 3 || texture_window_px % 2 == 0)
    bad("texture_window_px", "must be odd and >= 3");
  if (!(range_end_margin_px >= 0)) bad("range_end_margin_px", "must be >= 0");
}

FilterCounts filter_disparity(const cv::Mat& left_grey, const MatcherConfig& range,
                              const FilterConfig& config, cv::Mat& disparity,
                              FilterScratch& scratch) {
  if (disparity.type() != CV_32FC1 || left_grey.type() != CV_8UC1 ||
      disparity.size() != left_grey.size())
    throw std::invalid_argument(
        "filter_disparity: expected a CV_32F disparity and a CV_8UC1 image of its size");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float lo = static_cast<float>(range.min_disparity_px);
  const float hi = static_cast<float>(range.max_disparity_px() - config.range_end_margin_px);
  const bool texture = config.min_texture_dn > 0;
  if (texture) {
    left_grey.convertTo(scratch.grey_f, CV_32F);
    const cv::Size win(config.texture_window_px, config.texture_window_px);
    cv::boxFilter(scratch.grey_f, scratch.mean, CV_32F, win, cv::Point(-1, -1), true,
                  cv::BORDER_REFLECT);
    cv::sqrBoxFilter(scratch.grey_f, scratch.sq_mean, CV_32F, win, cv::Point(-1, -1), true,
                     cv::BORDER_REFLECT);
  }
  const float min_var = static_cast<float>(config.min_texture_dn * config.min_texture_dn);

  FilterCounts n;
  for (int y = 0; y < disparity.rows; ++y) {
    float* d = disparity.ptr<float>(y);
    const float* m = texture ? scratch.mean.ptr<float>(y) : nullptr;
    const float* q = texture ? scratch.sq_mean.ptr<float>(y) : nullptr;
    for (int x = 0; x < disparity.cols; ++x) {
      if (!(d[x] == d[x])) {
        ++n.unmatched;
      } else if (!(d[x] >= lo && d[x] <= hi)) {
        d[x] = nan;
        ++n.out_of_range;
      } else if (texture && q[x] - m[x] * m[x] < min_var) {
        d[x] = nan;
        ++n.textureless;
      }
    }
  }

  if (config.speckle_window_px > 0) {
    scratch.d16.create(disparity.size(), CV_16SC1);
    for (int y = 0; y < disparity.rows; ++y) {
      const float* d = disparity.ptr<float>(y);
      int16_t* o = scratch.d16.ptr<int16_t>(y);
      for (int x = 0; x < disparity.cols; ++x)
        o[x] = d[x] == d[x] ? static_cast<int16_t>(std::lround(d[x] * kSpeckleScale))
                            : kSpeckleUnknown;
    }
    cv::filterSpeckles(scratch.d16, kSpeckleUnknown, config.speckle_window_px,
                       static_cast<double>(config.speckle_range_px * kSpeckleScale),
                       scratch.speckle_buf);
    for (int y = 0; y < disparity.rows; ++y) {
      float* d = disparity.ptr<float>(y);
      const int16_t* o = scratch.d16.ptr<int16_t>(y);
      for (int x = 0; x < disparity.cols; ++x) {
        if (d[x] == d[x] && o[x] == kSpeckleUnknown) {
          d[x] = nan;
          ++n.speckles;
        }
      }
    }
  }
  n.known = cv::countNonZero(disparity == disparity);
  return n;
}

}  // namespace hd::recon
