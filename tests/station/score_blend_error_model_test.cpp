// The blend error model against a second computation: the blend drawn pixel by pixel with core's
// own per-pixel weight (core::continuous_pixel_weight, not the compositor's table), and against
// closed forms.
#include "station/score/blend_error_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/blend_weights.h"
#include "station/score/image_scores.h"

namespace hd::station {
namespace {

constexpr int kW = 120, kH = 90;             // the eye picture
constexpr int kFrameW = 160, kFrameH = 120;  // the video frame

struct Pictures {
  render::ImageRgba8 truth, model, video;
  std::vector<float> positions;  // (u, v) per pixel, NaN outside the video
};

// Smooth random pictures (errors that vary across the picture, as a warp's do) and positions of a
// zoomed, shifted frame, leaving a margin of pixels the video does not reach.
Pictures make_pictures(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> phase(0.0, 6.28);
  Pictures p;
  for (render::ImageRgba8* im : {&p.truth, &p.model, &p.video}) im->allocate(kW, kH);
  p.positions.assign(2 * kW * kH, NAN);
  const double a = phase(rng), b = phase(rng), c = phase(rng);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const double t = 128 + 60 * std::sin(0.07 * x + a) * std::cos(0.05 * y + b);
      const double s = t + 20 * std::sin(0.11 * x + 0.03 * y + c);
      const double v = t + 12 * std::cos(0.09 * x - 0.04 * y + a);
      for (int ch = 0; ch < 3; ++ch) {
        p.truth.pixel(x, y)[ch] = static_cast<uint8_t>(std::lround(t) + ch);
        p.model.pixel(x, y)[ch] = static_cast<uint8_t>(std::lround(s) + ch);
        p.video.pixel(x, y)[ch] = static_cast<uint8_t>(std::lround(v) + ch);
      }
      p.truth.pixel(x, y)[3] = p.model.pixel(x, y)[3] = p.video.pixel(x, y)[3] = 255;
      const double u = (x - 6 + 0.5) * 1.5, vv = (y - 5 + 0.5) * 1.5;
      if (u >= 0 && u < kFrameW && vv >= 0 && vv < kFrameH) {
        p.positions[2 * (y * kW + x)] = static_cast<float>(u);
        p.positions[2 * (y * kW + x) + 1] = static_cast<float>(vv);
      } else {  // the video does not reach: the pure video picture shows the model there
        for (int ch = 0; ch < 4; ++ch) p.video.pixel(x, y)[ch] = p.model.pixel(x, y)[ch];
      }
    }
  return p;
}

// The blend drawn pixel by pixel (no rounding), and its squared error.
double direct_sse(const Pictures& p, bool per_pixel, double w) {
  double sse = 0.0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float u = p.positions[2 * (y * kW + x)], v = p.positions[2 * (y * kW + x) + 1];
      double a = 0.0;
      if (!std::isnan(u))
        a = per_pixel ? core::continuous_pixel_weight(w, u, v, kFrameW, kFrameH) : w;
      for (int ch = 0; ch < 3; ++ch) {
        const double s = p.model.pixel(x, y)[ch], vid = p.video.pixel(x, y)[ch];
        const double e = s + a * (vid - s) - p.truth.pixel(x, y)[ch];
        sse += e * e;
      }
    }
  return sse;
}

BlendErrorModel model_of(const Pictures& p) {
  BlendErrorModel m;
  m.build(p.truth, p.model, p.video, p.positions.data(), kFrameW, kFrameH);
  return m;
}

TEST(BlendErrorModel, TheGlobalBlendIsExactAtEveryWeight) {
  const Pictures p = make_pictures(1);
  const BlendErrorModel m = model_of(p);
  for (double w : {0.0, 0.1, 0.37, 0.5, 0.81, 1.0}) {
    const double direct = direct_sse(p, false, w);
    EXPECT_NEAR(m.sse(core::TransitionMode::kGlobalBlend, w), direct, 1e-9 * direct) << w;
    EXPECT_NEAR(m.sse(core::TransitionMode::kAbrupt, w), direct, 1e-9 * direct) << w;
  }
}

TEST(BlendErrorModel, ThePureViewsAreThePicturesOwnPsnr) {
  const Pictures p = make_pictures(2);
  const BlendErrorModel m = model_of(p);
  EXPECT_NEAR(m.psnr_db(core::TransitionMode::kGlobalBlend, 0.0), psnr_db(p.model, p.truth), 1e-9);
  EXPECT_NEAR(m.psnr_db(core::TransitionMode::kGlobalBlend, 1.0), psnr_db(p.video, p.truth), 1e-9);
  EXPECT_NEAR(m.psnr_db(core::TransitionMode::kPerPixel, 1.0), psnr_db(p.video, p.truth), 1e-9);
}

// The grid over (x', y') is approximate only in the ramp's cells: within 0.01 dB of the blend
// drawn with core's exact weight, at every weight the per-pixel rule has a different shape.
TEST(BlendErrorModel, ThePerPixelBlendAgreesWithCoresWeightWithinAHundredthOfADecibel) {
  for (unsigned seed : {3u, 4u, 5u}) {
    const Pictures p = make_pictures(seed);
    const BlendErrorModel m = model_of(p);
    const double values = 3.0 * kW * kH;
    for (double w : {0.05, 0.25, 0.5, 0.62, 0.8, 0.95, 0.995}) {
      const double direct = psnr_from_mse(direct_sse(p, true, w) / values);
      const double model = m.psnr_db(core::TransitionMode::kPerPixel, w);
      EXPECT_NEAR(model, direct, 0.01) << "seed " << seed << " w " << w;
      // ...and the per-pixel picture differs from the global one (the rule is really applied).
      if (w < 0.9) {
        EXPECT_GT(std::abs(model - m.psnr_db(core::TransitionMode::kGlobalBlend, w)), 0.02)
            << "seed " << seed << " w " << w;
      }
    }
  }
}

TEST(BlendErrorModel, NoVideoScoresTheModelAtEveryWeight) {
  const Pictures p = make_pictures(6);
  BlendErrorModel m;
  m.build(p.truth, p.model, p.model, nullptr, 0, 0);
  EXPECT_FALSE(m.has_video());
  for (double w : {0.0, 0.5, 1.0})
    EXPECT_NEAR(m.psnr_db(core::TransitionMode::kPerPixel, w), psnr_db(p.model, p.truth), 1e-9);
}

TEST(BlendErrorModel, PicturesOfDifferentSizesAreRefused) {
  Pictures p = make_pictures(7);
  p.video.allocate(kW - 1, kH);
  BlendErrorModel m;
  EXPECT_THROW(m.build(p.truth, p.model, p.video, p.positions.data(), kFrameW, kFrameH),
               std::invalid_argument);
}

}  // namespace
}  // namespace hd::station
