#include "recon/disparity_score.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace hd::recon {

namespace {
bool known(float v) {
  return v == v && v > 0.0f;
}
}  // namespace

cv::Mat non_occluded_mask(const cv::Mat& truth, float tol) {
  if (truth.type() != CV_32FC1) throw std::invalid_argument("non_occluded_mask: expected CV_32F");
  cv::Mat mask = cv::Mat::zeros(truth.size(), CV_8UC1);
  std::vector<float> nearest(static_cast<std::size_t>(truth.cols));
  for (int y = 0; y < truth.rows; ++y) {
    const float* t = truth.ptr<float>(y);
    std::fill(nearest.begin(), nearest.end(), -1.0f);
    auto target = [&](int x) { return static_cast<int>(std::lround(x - t[x])); };
    for (int x = 0; x < truth.cols; ++x) {
      if (!known(t[x])) continue;
      const int xr = target(x);
      if (xr >= 0 && xr < truth.cols)
        nearest[static_cast<std::size_t>(xr)] =
            std::max(nearest[static_cast<std::size_t>(xr)], t[x]);
    }
    uchar* m = mask.ptr<uchar>(y);
    for (int x = 0; x < truth.cols; ++x) {
      if (!known(t[x])) continue;
      const int xr = target(x);
      if (xr < 0 || xr >= truth.cols) continue;
      if (t[x] < nearest[static_cast<std::size_t>(xr)] - tol) continue;
      m[x] = 1;
    }
  }
  return mask;
}

cv::Mat fill_holes(const cv::Mat& disparity) {
  cv::Mat out = disparity.clone();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> from_left(static_cast<std::size_t>(out.cols));
  for (int y = 0; y < out.rows; ++y) {
    float* d = out.ptr<float>(y);
    float last = nan;
    for (int x = 0; x < out.cols; ++x) {
      if (d[x] == d[x]) last = d[x];
      from_left[static_cast<std::size_t>(x)] = last;
    }
    last = nan;
    for (int x = out.cols - 1; x >= 0; --x) {
      if (d[x] == d[x]) {
        last = d[x];
        continue;
      }
      const float a = from_left[static_cast<std::size_t>(x)];
      d[x] = !(a == a) ? last : !(last == last) ? a : std::min(a, last);
    }
  }
  return out;
}

DisparityScore score_disparity(const cv::Mat& disparity, const cv::Mat& truth, const cv::Mat& mask,
                               double tau_px) {
  if (disparity.type() != CV_32FC1 || truth.type() != CV_32FC1 || mask.type() != CV_8UC1 ||
      disparity.size() != truth.size() || mask.size() != truth.size())
    throw std::invalid_argument("score_disparity: expected CV_32F maps and a CV_8U mask, one size");
  const cv::Mat filled = fill_holes(disparity);
  DisparityScore s;
  int with = 0, bad_h = 0, bad_f = 0, bad_k = 0;
  std::vector<float> err;
  for (int y = 0; y < truth.rows; ++y) {
    const float* d = disparity.ptr<float>(y);
    const float* f = filled.ptr<float>(y);
    const float* t = truth.ptr<float>(y);
    const uchar* m = mask.ptr<uchar>(y);
    for (int x = 0; x < truth.cols; ++x) {
      if (!m[x]) continue;
      ++s.pixels;
      if (d[x] == d[x]) {
        ++with;
        const float e = std::abs(d[x] - t[x]);
        err.push_back(e);
        if (e > tau_px) {
          ++bad_h;
          ++bad_k;
        }
      } else {
        ++bad_h;
      }
      if (!(std::abs(f[x] - t[x]) <= tau_px)) ++bad_f;
    }
  }
  if (s.pixels == 0) return s;
  const double n = s.pixels;
  s.density = with / n;
  s.bad_holes = bad_h / n;
  s.bad_filled = bad_f / n;
  s.bad_known = with > 0 ? static_cast<double>(bad_k) / with : 0.0;
  if (!err.empty()) {
    std::nth_element(err.begin(), err.begin() + static_cast<std::ptrdiff_t>(err.size() / 2),
                     err.end());
    s.median_abs_px = err[err.size() / 2];
  }
  return s;
}

}  // namespace hd::recon
