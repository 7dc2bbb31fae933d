#include "station/score/blend_error_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "render/compositor/border_weight.h"
#include "station/score/image_scores.h"

namespace hd::station {
namespace {

// The cell of a position along one axis. The ramp lies against the frame's edge, within kappa of
// it in x' (kappa = 2 (1 - w) for w >= 1/2, small when the video is nearly opaque), so the cells
// are finer there: cell i holds r = 1 - x' in [(i / kBins)^2, ((i + 1) / kBins)^2), from
// 1/4096 of the half frame at the edge to 1/32 in the middle.
int bin_of(float p, float two_over_size) {
  const float r = 1.0f - std::min(std::abs(1.0f - p * two_over_size), 1.0f);
  return std::min(static_cast<int>(std::sqrt(r) * BlendErrorModel::kBins),
                  BlendErrorModel::kBins - 1);
}

// The frame position (u or v) at the middle of cell i along an axis of `size` pixels.
double centre_of(int i, double size) {
  const double s = (i + 0.5) / BlendErrorModel::kBins;
  return s * s * 0.5 * size;  // u = (1 - x') size / 2 = r size / 2
}

}  // namespace

void BlendErrorModel::build(const render::ImageRgba8& truth, const render::ImageRgba8& model,
                            const render::ImageRgba8& video, const float* positions,
                            int frame_width, int frame_height) {
  if (truth.width != model.width || truth.height != model.height || truth.width != video.width ||
      truth.height != video.height || truth.empty())
    throw std::invalid_argument(
        "blend error model: pictures of different sizes (truth " + std::to_string(truth.width) +
        "x" + std::to_string(truth.height) + ", model " + std::to_string(model.width) + "x" +
        std::to_string(model.height) + ", video " + std::to_string(video.width) + "x" +
        std::to_string(video.height) + ")");
  has_video_ = positions != nullptr && frame_width > 0 && frame_height > 0;
  frame_width_ = frame_width;
  frame_height_ = frame_height;
  values_ = 3.0 * truth.width * static_cast<double>(truth.height);
  const std::size_t cells = static_cast<std::size_t>(kBins) * kBins;
  bin_bd_.assign(cells, 0.0);
  bin_dd_.assign(cells, 0.0);
  const float two_over_w = has_video_ ? 2.0f / static_cast<float>(frame_width) : 0.0f;
  const float two_over_h = has_video_ ? 2.0f / static_cast<float>(frame_height) : 0.0f;
  int64_t bb = 0, bd = 0, dd = 0;  // exact: at most 3 * 510^2 per pixel
  for (int y = 0; y < truth.height; ++y) {
    const uint8_t* t = truth.row(y);
    const uint8_t* s = model.row(y);
    const uint8_t* v = video.row(y);
    const float* uv =
        has_video_ ? positions + 2 * static_cast<std::size_t>(y) * truth.width : nullptr;
    for (int x = 0; x < truth.width; ++x) {
      int pb = 0, pd = 0, pdd = 0;
      for (int c = 0; c < 3; ++c) {
        const int b = int(s[4 * x + c]) - int(t[4 * x + c]);
        const int d = int(v[4 * x + c]) - int(s[4 * x + c]);
        pb += b * b;
        pd += b * d;
        pdd += d * d;
      }
      bb += pb;
      if (!has_video_ || std::isnan(uv[2 * x]) || pdd == 0) continue;
      bd += pd;
      dd += pdd;
      const std::size_t cell = static_cast<std::size_t>(bin_of(uv[2 * x + 1], two_over_h)) * kBins +
                               static_cast<std::size_t>(bin_of(uv[2 * x], two_over_w));
      bin_bd_[cell] += pd;
      bin_dd_[cell] += pdd;
    }
  }
  sse_model_ = static_cast<double>(bb);
  sum_bd_ = static_cast<double>(bd);
  sum_dd_ = static_cast<double>(dd);
}

double BlendErrorModel::sse(core::TransitionMode mode, double w) const {
  w = std::isnan(w) ? 0.0 : std::clamp(w, 0.0, 1.0);
  if (!has_video_ || w <= 0.0) return sse_model_;
  if (mode != core::TransitionMode::kPerPixel || w >= 1.0)
    return sse_model_ + 2.0 * w * sum_bd_ + w * w * sum_dd_;
  const render::BorderWeight weight(w, frame_width_, frame_height_);
  double e = sse_model_;
  for (int j = 0; j < kBins; ++j) {
    const double v = centre_of(j, frame_height_);
    for (int i = 0; i < kBins; ++i) {
      const std::size_t cell = static_cast<std::size_t>(j) * kBins + static_cast<std::size_t>(i);
      if (bin_dd_[cell] == 0.0) continue;
      const double a = weight(centre_of(i, frame_width_), v);
      e += 2.0 * a * bin_bd_[cell] + a * a * bin_dd_[cell];
    }
  }
  return std::max(e, 0.0);
}

double BlendErrorModel::psnr_db(core::TransitionMode mode, double w) const {
  return psnr_from_mse(sse(mode, w) / values_);
}

}  // namespace hd::station
