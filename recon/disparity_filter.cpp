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
// Below this grey-level variance (DN^2) a window is flat: its correlation is undefined (0).
constexpr float kMinVariance = 0.25f;
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
  if (!(min_correlation >= -1 && min_correlation <= 1)) bad("min_correlation", "must be in -1..1");
  if (correlation_window_px < 3 || correlation_window_px % 2 == 0)
    bad("correlation_window_px", "must be odd and >= 3");
  if (correlation_region_px < 1 || correlation_region_px % 2 == 0)
    bad("correlation_region_px", "must be odd and >= 1");
}

FilterCounts filter_disparity(const cv::Mat& left_grey, const cv::Mat& right_grey,
                              const MatcherConfig& range, const FilterConfig& config,
                              cv::Mat& disparity, FilterScratch& scratch) {
  if (disparity.type() != CV_32FC1 || left_grey.type() != CV_8UC1 || right_grey.type() != CV_8UC1 ||
      disparity.size() != left_grey.size() || right_grey.size() != left_grey.size())
    throw std::invalid_argument(
        "filter_disparity: expected a CV_32F disparity and two CV_8UC1 images of its size");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float lo = static_cast<float>(range.min_disparity_px);
  const float hi = static_cast<float>(range.max_disparity_px() - config.range_end_margin_px);
  const bool texture = config.min_texture_dn > 0;
  left_grey.convertTo(scratch.grey_f, CV_32F);
  if (texture) {
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

  if (config.min_correlation > -1) {
    // The right image resampled at each pixel's match (x - d, y); unknown pixels sample far
    // outside and take the border value, their correlation is not used.
    scratch.map_x.create(disparity.size(), CV_32FC1);
    scratch.map_y.create(disparity.size(), CV_32FC1);
    for (int y = 0; y < disparity.rows; ++y) {
      const float* d = disparity.ptr<float>(y);
      float* mx = scratch.map_x.ptr<float>(y);
      float* my = scratch.map_y.ptr<float>(y);
      for (int x = 0; x < disparity.cols; ++x) {
        mx[x] = d[x] == d[x] ? static_cast<float>(x) - d[x] : -1.0f;
        my[x] = static_cast<float>(y);
      }
    }
    cv::remap(right_grey, scratch.warped, scratch.map_x, scratch.map_y, cv::INTER_LINEAR,
              cv::BORDER_REPLICATE);
    scratch.warped.convertTo(scratch.warped, CV_32F);
    const cv::Size win(config.correlation_window_px, config.correlation_window_px);
    const cv::Point anchor(-1, -1);
    cv::Mat& lm = texture && config.texture_window_px == config.correlation_window_px
                      ? scratch.mean
                      : scratch.prod;  // reuse the texture pass's means when the windows agree
    cv::Mat& lq = texture && config.texture_window_px == config.correlation_window_px
                      ? scratch.sq_mean
                      : scratch.cross;
    if (&lm == &scratch.prod) {
      cv::boxFilter(scratch.grey_f, lm, CV_32F, win, anchor, true, cv::BORDER_REFLECT);
      cv::sqrBoxFilter(scratch.grey_f, lq, CV_32F, win, anchor, true, cv::BORDER_REFLECT);
    }
    cv::boxFilter(scratch.warped, scratch.w_mean, CV_32F, win, anchor, true, cv::BORDER_REFLECT);
    cv::sqrBoxFilter(scratch.warped, scratch.w_sq, CV_32F, win, anchor, true, cv::BORDER_REFLECT);
    cv::Mat lr;
    cv::multiply(scratch.grey_f, scratch.warped, lr);
    cv::boxFilter(lr, lr, CV_32F, win, anchor, true, cv::BORDER_REFLECT);
    // Per pixel ZNCC (0 where unknown or flat), then its mean over the known pixels of a
    // correlation_region_px square: a surface outside the range is uncorrelated as a whole,
    // while a correct match at a depth edge or a JPEG block is uncorrelated only in a thin band.
    scratch.zncc.create(disparity.size(), CV_32FC1);
    scratch.zknown.create(disparity.size(), CV_32FC1);
    for (int y = 0; y < disparity.rows; ++y) {
      const float* d = disparity.ptr<float>(y);
      const float *a = lm.ptr<float>(y), *aa = lq.ptr<float>(y);
      const float *b = scratch.w_mean.ptr<float>(y), *bb = scratch.w_sq.ptr<float>(y);
      const float* ab = lr.ptr<float>(y);
      float* z = scratch.zncc.ptr<float>(y);
      float* k = scratch.zknown.ptr<float>(y);
      for (int x = 0; x < disparity.cols; ++x) {
        const float va = aa[x] - a[x] * a[x], vb = bb[x] - b[x] * b[x];
        const bool known = d[x] == d[x];
        k[x] = known ? 1.0f : 0.0f;
        z[x] = known && va > kMinVariance && vb > kMinVariance
                   ? (ab[x] - a[x] * b[x]) / std::sqrt(va * vb)
                   : 0.0f;
      }
    }
    if (config.correlation_region_px > 1) {
      const cv::Size region(config.correlation_region_px, config.correlation_region_px);
      cv::boxFilter(scratch.zncc, scratch.zncc, CV_32F, region, anchor, false, cv::BORDER_REFLECT);
      cv::boxFilter(scratch.zknown, scratch.zknown, CV_32F, region, anchor, false,
                    cv::BORDER_REFLECT);
    }
    const float t = static_cast<float>(config.min_correlation);
    for (int y = 0; y < disparity.rows; ++y) {
      float* d = disparity.ptr<float>(y);
      const float* z = scratch.zncc.ptr<float>(y);
      const float* k = scratch.zknown.ptr<float>(y);
      for (int x = 0; x < disparity.cols; ++x) {
        if (!(d[x] == d[x])) continue;
        if (!(z[x] >= t * k[x])) {  // mean correlation of the known neighbours < t
          d[x] = nan;
          ++n.uncorrelated;
        }
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
