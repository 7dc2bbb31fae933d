#pragma once
// How far the picture the operator saw is from the truth: PSNR, SSIM and GMSD of one eye
// (OpenCV's quality module), and PSNR over the pixels a mask selects (those that showed video,
// those that showed the model), for `hybrid-station score`.
//
// Pictures are RGBA8 as the compositor draws them; alpha is ignored and the three colour channels
// count alike. PSNR = 10 log10(255^2 / MSE) over every selected pixel and channel. Two identical
// pictures would give +inf; they give kPsnrCapDb instead, so means and percentiles over a run stay
// finite (a frame at the cap is exact to the last bit). SSIM and GMSD are computed on the luma
// (BT.601, cv::COLOR_RGBA2GRAY), as both metrics' authors define them for grey pictures and as
// video quality tools report them: colour errors count through PSNR. SSIM 1 and GMSD 0 mean
// identical.

#include <cstdint>
#include <span>

#include "render/compositor/image_rgba8.h"

namespace hd::station {

/// The PSNR reported for identical pictures. A picture that differs scores above it only when
/// fewer than one channel value in 150,000 is off by one (MSE < 255^2 / 10^10), so it is a cap on
/// what is reported, not a bound on what is possible.
inline constexpr double kPsnrCapDb = 100.0;

struct ImageScores {
  double psnr_db = 0.0;
  double ssim = 0.0;
  double gmsd = 0.0;
};

/// The three scores of `shown` against `truth` (same size; throws std::invalid_argument).
ImageScores score_image(const render::ImageRgba8& shown, const render::ImageRgba8& truth);

/// PSNR alone (one integer pass; no SSIM or GMSD).
double psnr_db(const render::ImageRgba8& shown, const render::ImageRgba8& truth);

/// PSNR over the pixels whose mask byte is non-zero (`mask`: width x height, row-major); NaN
/// when it selects none.
double masked_psnr_db(const render::ImageRgba8& shown, const render::ImageRgba8& truth,
                      std::span<const uint8_t> mask);

/// The error split by what each pixel showed, from the compositor's per-pixel video weight
/// (render::CpuCompositor::record_video_weight, 0..255): PSNR over the pixels that showed video
/// only (255), a blend (1..254) and the model only (0), NaN where there were none; and the mean
/// weight, the share of the picture that came from the video. One pass.
struct WeightSplit {
  double psnr_video_db = 0.0, psnr_blend_db = 0.0, psnr_synthetic_db = 0.0;
  double video_fraction = 0.0;
  /// The share of pixels that showed mostly video (weight >= 128 of 255).
  double video_dominant_fraction = 0.0;
};
/// `weights`: the weight of pixel (x, y) at weights[y * stride + x].
WeightSplit split_by_weight(const render::ImageRgba8& shown, const render::ImageRgba8& truth,
                            const uint8_t* weights, std::size_t stride);

/// PSNR of a mean squared error (per channel value, 8-bit), capped at kPsnrCapDb.
double psnr_from_mse(double mse);

}  // namespace hd::station
