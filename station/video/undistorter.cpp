#include "station/video/undistorter.h"

#include <cstddef>
#include <cstring>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "core/opencv_pixels.h"
#include "station/video/frame_copy.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hd::station {
namespace {

// OpenCV's fixed-point remap: fractions in 1/32 pixel (INTER_BITS = 5).
constexpr int kFracBits = 5;
constexpr int kFracSize = 1 << kFracBits;

// OpenCV puts pixel centres at integer coordinates, the project at +0.5 (core/opencv_pixels.h).
cv::Matx33d opencv_camera_matrix(const core::Pinhole& pinhole) {
  const core::OpenCvIntrinsics p = core::to_opencv(pinhole);
  return {p.fx, 0.0, p.cx, 0.0, p.fy, p.cy, 0.0, 0.0, 1.0};
}

}  // namespace

bool Undistorter::needed(const core::Pinhole& p_c) {
  for (int i = 0; i < p_c.distortion_count && i < static_cast<int>(p_c.distortion.size()); ++i)
    if (p_c.distortion[static_cast<std::size_t>(i)] != 0.0) return true;
  return false;
}

Undistorter::Undistorter(const core::Pinhole& p_c) : width_(p_c.width), height_(p_c.height) {
  if (!p_c.valid())
    throw std::invalid_argument("undistorter: camera intrinsics are not a valid pinhole");
  const int n = p_c.distortion_count;
  if (n != 0 && n != 4 && n != 5 && n != 8)
    throw std::invalid_argument("undistorter: distortion_count must be 0, 4, 5 or 8, got " +
                                std::to_string(n));
  cv::Mat dist(1, n == 0 ? 4 : n, CV_64F, cv::Scalar(0));
  for (int i = 0; i < n; ++i) dist.at<double>(i) = p_c.distortion[static_cast<std::size_t>(i)];
  const cv::Matx33d K = opencv_camera_matrix(p_c);
  cv::Mat map1, map2;
  cv::initUndistortRectifyMap(K, dist, cv::noArray(), K, cv::Size(width_, height_), CV_16SC2, map1,
                              map2);
  const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  map_xy_.resize(pixels * 2);
  map_frac_.resize(pixels);
  for (int y = 0; y < height_; ++y) {
    const auto* xy = map1.ptr<cv::Vec2s>(y);
    const auto* fr = map2.ptr<uint16_t>(y);
    for (int x = 0; x < width_; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                            static_cast<std::size_t>(x);
      map_xy_[2 * i] = xy[x][0];
      map_xy_[2 * i + 1] = xy[x][1];
      map_frac_[i] = static_cast<uint16_t>(fr[x] & (kFracSize * kFracSize - 1));
    }
  }
}

void Undistorter::source_of(int x, int y, double& u, double& v) const {
  const std::size_t i =
      static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  const int a = map_frac_[i];
  u = map_xy_[2 * i] + static_cast<double>(a & (kFracSize - 1)) / kFracSize + 0.5;
  v = map_xy_[2 * i + 1] + static_cast<double>(a >> kFracBits) / kFracSize + 0.5;
}

bool Undistorter::apply(const drivers::Frame& src, drivers::Frame& dst) const {
  if (width_ <= 0 || !is_rgba_frame(src, width_, height_) || !is_rgba_frame(dst, width_, height_))
    return false;
  const int w = width_, h = height_;
  const uint8_t* s = src.data.data();
  const std::ptrdiff_t ss = src.stride_bytes;
  for (int y = 0; y < h; ++y) {
    uint8_t* out = dst.data.data() + static_cast<std::ptrdiff_t>(y) * dst.stride_bytes;
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const int16_t* xy = map_xy_.data() + 2 * row;
    const uint16_t* fr = map_frac_.data() + row;
    for (int x = 0; x < w; ++x, out += 4) {
      const int sx = xy[2 * x], sy = xy[2 * x + 1];
      const int fx = fr[x] & (kFracSize - 1), fy = fr[x] >> kFracBits;
      // Weights sum to 1024 = 32 * 32: with 1/32 fractions the bilinear products are exact
      // integers, the same values cv::remap's table holds scaled by 32.
      const int w00 = (kFracSize - fx) * (kFracSize - fy), w10 = fx * (kFracSize - fy);
      const int w01 = (kFracSize - fx) * fy, w11 = fx * fy;
      if (sx >= 0 && sy >= 0 && sx + 1 < w && sy + 1 < h) {
        const uint8_t* p0 = s + sy * ss + 4 * sx;
        const uint8_t* p1 = p0 + ss;
#if defined(__SSE2__)
        // Same integer sums as the scalar branch, four channels at once: each row's two pixels
        // are paired per channel (r0 r1 g0 g1 ...) and multiplied-added with (w_left, w_right).
        const __m128i zero = _mm_setzero_si128();
        const __m128i a =
            _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p0)), zero);
        const __m128i b =
            _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p1)), zero);
        const __m128i a_pairs = _mm_unpacklo_epi16(a, _mm_srli_si128(a, 8));
        const __m128i b_pairs = _mm_unpacklo_epi16(b, _mm_srli_si128(b, 8));
        const __m128i wa = _mm_set1_epi32(
            static_cast<int>((static_cast<uint32_t>(w10) << 16) | static_cast<uint32_t>(w00)));
        const __m128i wb = _mm_set1_epi32(
            static_cast<int>((static_cast<uint32_t>(w11) << 16) | static_cast<uint32_t>(w01)));
        __m128i sum = _mm_add_epi32(_mm_madd_epi16(a_pairs, wa), _mm_madd_epi16(b_pairs, wb));
        sum = _mm_srli_epi32(_mm_add_epi32(sum, _mm_set1_epi32(512)), 10);
        const __m128i packed = _mm_packus_epi16(_mm_packs_epi32(sum, zero), zero);
        const int rgba = _mm_cvtsi128_si32(packed);
        std::memcpy(out, &rgba, 4);
#else
        for (int c = 0; c < 4; ++c)
          out[c] = static_cast<uint8_t>(
              (w00 * p0[c] + w10 * p0[4 + c] + w01 * p1[c] + w11 * p1[4 + c] + 512) >> 10);
#endif
      } else {
        // Border: neighbours outside the frame are transparent black (BORDER_CONSTANT 0).
        const bool x0 = sx >= 0 && sx < w, x1 = sx + 1 >= 0 && sx + 1 < w;
        const bool y0 = sy >= 0 && sy < h, y1 = sy + 1 >= 0 && sy + 1 < h;
        for (int c = 0; c < 4; ++c) {
          int acc = 512;
          if (y0 && x0) acc += w00 * s[sy * ss + 4 * sx + c];
          if (y0 && x1) acc += w10 * s[sy * ss + 4 * (sx + 1) + c];
          if (y1 && x0) acc += w01 * s[(sy + 1) * ss + 4 * sx + c];
          if (y1 && x1) acc += w11 * s[(sy + 1) * ss + 4 * (sx + 1) + c];
          out[c] = static_cast<uint8_t>(acc >> 10);
        }
      }
    }
  }
  copy_frame_stamps(src, dst);
  return true;
}

}  // namespace hd::station
