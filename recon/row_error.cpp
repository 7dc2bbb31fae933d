#include "recon/row_error.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <vector>

namespace hd::recon {

namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<std::ptrdiff_t>(std::lround(q * (v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[static_cast<std::size_t>(k)];
}

}  // namespace

RowError measure_row_error(const cv::Mat& left_grey, const cv::Mat& right_grey,
                           const cv::Mat& disparity, int max_features) {
  RowError out;
  if (left_grey.empty() || left_grey.type() != CV_8UC1 || right_grey.size() != left_grey.size() ||
      right_grey.type() != CV_8UC1 || disparity.size() != left_grey.size() ||
      disparity.type() != CV_32FC1)
    return out;
  std::vector<cv::Point2f> corners;
  // Corners at least 8 px apart, 1 % of the strongest response: spread over the image.
  cv::goodFeaturesToTrack(left_grey, corners, max_features, 0.01, 8.0);
  std::vector<cv::Point2f> from, guess;
  for (const cv::Point2f& p : corners) {
    const int x = static_cast<int>(std::lround(p.x)), y = static_cast<int>(std::lround(p.y));
    if (x < 0 || y < 0 || x >= disparity.cols || y >= disparity.rows) continue;
    const float d = disparity.at<float>(y, x);
    if (!(d == d)) continue;
    from.push_back(p);
    guess.emplace_back(p.x - d, p.y);
  }
  if (static_cast<int>(from.size()) < RowError::kMinFeatures) return out;
  const cv::Size win(15, 15);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<uchar> ok, ok_back;
  std::vector<float> err;
  std::vector<cv::Point2f> to = guess;
  cv::calcOpticalFlowPyrLK(left_grey, right_grey, from, to, ok, err, win, 1, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<cv::Point2f> back = from;
  cv::calcOpticalFlowPyrLK(right_grey, left_grey, to, back, ok_back, err, win, 1, stop,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  std::vector<double> dy, ady;
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (!ok[i] || !ok_back[i]) continue;
    if (std::hypot(back[i].x - from[i].x, back[i].y - from[i].y) > 0.5) continue;
    const double v = to[i].y - from[i].y;
    dy.push_back(v);
    ady.push_back(std::abs(v));
  }
  out.features = static_cast<int>(dy.size());
  out.median_px = quantile(dy, 0.5);
  out.median_abs_px = quantile(ady, 0.5);
  out.p90_abs_px = quantile(ady, 0.9);
  return out;
}

}  // namespace hd::recon
