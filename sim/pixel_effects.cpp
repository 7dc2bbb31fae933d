#include "sim/pixel_effects.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/opencv_pixels.h"
#include "sim/sim_random.h"

namespace hd::sim {

namespace {

// std::lround of the clamped value, written out: non-negative, so round half away from zero is
// truncation of v + 0.5. The libm call per channel value was 4% of a `score` run.
uint8_t clip_dn(double v) {
  return static_cast<uint8_t>(static_cast<int>(std::clamp(v, 0.0, 255.0) + 0.5));
}

}  // namespace

SensorNoise::SensorNoise(const SensorNoiseEffect& effect, uint64_t camera_stream)
    : effect_(effect), stream_(camera_stream) {}

void SensorNoise::apply(drivers::Frame& frame) const {
  // Sum of four uniforms on [0, 65535]: mean 4 * 32767.5, variance 4 * (65536^2 - 1) / 12.
  constexpr double kMean = 4.0 * 32767.5;
  const double scale = effect_.sigma_dn / std::sqrt(4.0 * (65536.0 * 65536.0 - 1.0) / 12.0);
  uint64_t state = random_bits(effect_.seed, stream_, frame.sequence) | 1u;
  for (int y = 0; y < frame.height; ++y) {
    uint8_t* row = frame.data.data() + static_cast<std::ptrdiff_t>(y) * frame.stride_bytes;
    for (int x = 0; x < frame.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        state ^= state << 13;  // xorshift64
        state ^= state >> 7;
        state ^= state << 17;
        const uint64_t r = state;
        const double sum = static_cast<double>((r & 0xFFFF) + ((r >> 16) & 0xFFFF) +
                                               ((r >> 32) & 0xFFFF) + (r >> 48));
        uint8_t& p = row[4 * x + c];
        p = clip_dn(p + (sum - kMean) * scale);
      }
    }
  }
}

ExposureLut::ExposureLut(const ExposureEffect& effect) {
  for (int i = 0; i < 256; ++i)
    lut_[static_cast<std::size_t>(i)] = clip_dn(effect.gain * i + effect.offset_dn);
}

void ExposureLut::apply(drivers::Frame& frame) const {
  for (int y = 0; y < frame.height; ++y) {
    uint8_t* row = frame.data.data() + static_cast<std::ptrdiff_t>(y) * frame.stride_bytes;
    for (int x = 0; x < frame.width; ++x) {
      row[4 * x] = lut_[row[4 * x]];
      row[4 * x + 1] = lut_[row[4 * x + 1]];
      row[4 * x + 2] = lut_[row[4 * x + 2]];
    }
  }
}

LensDistorter::LensDistorter(const core::Pinhole& k) {
  // Worked in OpenCV's numbers (pixel centres at integers, core/opencv_pixels.h): remap's map
  // holds exactly the source coordinates undistortPoints returns.
  const core::OpenCvIntrinsics o = core::to_opencv(k);
  const cv::Matx33d K(o.fx, 0, o.cx, 0, o.fy, o.cy, 0, 0, 1);
  const int n = std::max(k.distortion_count, 5);
  cv::Mat D(1, n, CV_64F);
  for (int i = 0; i < n; ++i) D.at<double>(i) = k.distortion[static_cast<std::size_t>(i)];
  std::vector<cv::Point2d> distorted;
  distorted.reserve(static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height));
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) distorted.emplace_back(u, v);
  }
  std::vector<cv::Point2d> ideal;
  cv::undistortPoints(distorted, ideal, K, D, cv::noArray(), K,
                      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 1e-9));
  cv::Mat map(k.height, k.width, CV_32FC2);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const cv::Point2d& p = ideal[static_cast<std::size_t>(v) * k.width + u];
      map.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(p.x), static_cast<float>(p.y));
    }
  }
  cv::convertMaps(map, cv::noArray(), map1_, map2_, CV_16SC2);
}

void LensDistorter::apply(const render::ImageRgba8& ideal, drivers::Frame& out) const {
  const cv::Mat src(ideal.height, ideal.width, CV_8UC4, const_cast<uint8_t*>(ideal.data.data()),
                    static_cast<std::size_t>(ideal.stride_bytes));
  cv::Mat dst(out.height, out.width, CV_8UC4, out.data.data(),
              static_cast<std::size_t>(out.stride_bytes));
  cv::remap(src, dst, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
}

}  // namespace hd::sim
