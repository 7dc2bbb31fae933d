#include "station/score/image_scores.h"

#include <cmath>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/quality.hpp>
#include <stdexcept>
#include <string>

namespace hd::station {
namespace {

// The picture's luma, Y = 0.299 R + 0.587 G + 0.114 B (BT.601, OpenCV's RGBA2GRAY), 8-bit.
cv::Mat luma(const render::ImageRgba8& im) {
  const cv::Mat rgba(im.height, im.width, CV_8UC4, const_cast<uint8_t*>(im.data.data()),
                     static_cast<std::size_t>(im.stride_bytes));
  cv::Mat y;
  cv::cvtColor(rgba, y, cv::COLOR_RGBA2GRAY);
  return y;
}

void check_sizes(const render::ImageRgba8& a, const render::ImageRgba8& b) {
  if (a.width != b.width || a.height != b.height || a.empty())
    throw std::invalid_argument("score: pictures of different sizes (" + std::to_string(a.width) +
                                "x" + std::to_string(a.height) + " against " +
                                std::to_string(b.width) + "x" + std::to_string(b.height) + ")");
}

}  // namespace

double psnr_from_mse(double mse) {
  if (!(mse > 0.0)) return kPsnrCapDb;
  return std::min(kPsnrCapDb, 10.0 * std::log10(255.0 * 255.0 / mse));
}

// Over all pixels and channels: QualityPSNR's per-channel figures would be averaged in dB, which
// is not the PSNR of the picture.
double psnr_db(const render::ImageRgba8& shown, const render::ImageRgba8& truth) {
  check_sizes(shown, truth);
  int64_t sse = 0;  // exact: at most 3 * 255^2 per pixel
  for (int y = 0; y < shown.height; ++y) {
    const uint8_t* p = shown.row(y);
    const uint8_t* q = truth.row(y);
    for (int i = 0; i < 4 * shown.width; ++i) {
      const int d = (i & 3) == 3 ? 0 : int(p[i]) - int(q[i]);
      sse += d * d;
    }
  }
  return psnr_from_mse(static_cast<double>(sse) /
                       (3.0 * shown.width * static_cast<double>(shown.height)));
}

ImageScores score_image(const render::ImageRgba8& shown, const render::ImageRgba8& truth) {
  check_sizes(shown, truth);
  const cv::Mat a = luma(shown), b = luma(truth);
  ImageScores s;
  s.psnr_db = psnr_db(shown, truth);
  s.ssim = cv::quality::QualitySSIM::compute(b, a, cv::noArray())[0];
  s.gmsd = cv::quality::QualityGMSD::compute(b, a, cv::noArray())[0];
  return s;
}

double masked_psnr_db(const render::ImageRgba8& shown, const render::ImageRgba8& truth,
                      std::span<const uint8_t> mask) {
  check_sizes(shown, truth);
  if (mask.size() != static_cast<std::size_t>(shown.width) * static_cast<std::size_t>(shown.height))
    throw std::invalid_argument("score: mask of " + std::to_string(mask.size()) +
                                " bytes for a picture of " + std::to_string(shown.width) + "x" +
                                std::to_string(shown.height));
  double sse = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < shown.height; ++y) {
    const uint8_t* p = shown.row(y);
    const uint8_t* q = truth.row(y);
    const uint8_t* m = mask.data() + static_cast<std::size_t>(y) * shown.width;
    for (int x = 0; x < shown.width; ++x) {
      if (m[x] == 0) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = double(p[4 * x + c]) - double(q[4 * x + c]);
        sse += d * d;
      }
      n += 3;
    }
  }
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  return psnr_from_mse(sse / static_cast<double>(n));
}

WeightSplit split_by_weight(const render::ImageRgba8& shown, const render::ImageRgba8& truth,
                            const uint8_t* weights, std::size_t stride) {
  check_sizes(shown, truth);
  int64_t sse[3] = {0, 0, 0};  // synthetic, blend, video
  int64_t n[3] = {0, 0, 0};
  int64_t weight_sum = 0, video_dominant = 0;
  for (int y = 0; y < shown.height; ++y) {
    const uint8_t* p = shown.row(y);
    const uint8_t* q = truth.row(y);
    const uint8_t* w = weights + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < shown.width; ++x) {
      int e = 0;
      for (int c = 0; c < 3; ++c) {
        const int d = int(p[4 * x + c]) - int(q[4 * x + c]);
        e += d * d;
      }
      const int k = w[x] == 0 ? 0 : w[x] == 255 ? 2 : 1;
      sse[k] += e;
      n[k] += 3;
      weight_sum += w[x];
      video_dominant += w[x] >= 128 ? 1 : 0;
    }
  }
  const auto psnr = [&](int k) {
    return n[k] ? psnr_from_mse(static_cast<double>(sse[k]) / static_cast<double>(n[k]))
                : std::numeric_limits<double>::quiet_NaN();
  };
  WeightSplit out;
  out.psnr_synthetic_db = psnr(0);
  out.psnr_blend_db = psnr(1);
  out.psnr_video_db = psnr(2);
  out.video_dominant_fraction =
      static_cast<double>(video_dominant) / (shown.width * static_cast<double>(shown.height));
  out.video_fraction =
      static_cast<double>(weight_sum) / (255.0 * shown.width * static_cast<double>(shown.height));
  return out;
}

}  // namespace hd::station
