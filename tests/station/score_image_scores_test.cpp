// Image scores against closed forms and against OpenCV's own cv::PSNR (a second implementation).
#include "station/score/image_scores.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

namespace hd::station {
namespace {

render::ImageRgba8 filled(int w, int h, uint8_t v) {
  render::ImageRgba8 im;
  im.allocate(w, h);
  for (std::size_t i = 0; i < im.data.size(); ++i) im.data[i] = (i % 4 == 3) ? 255 : v;
  return im;
}

TEST(ImageScores, AConstantOffsetGivesTheClosedFormPsnr) {
  const render::ImageRgba8 truth = filled(64, 48, 100), shown = filled(64, 48, 110);
  const ImageScores s = score_image(shown, truth);
  // MSE = 10^2 = 100: PSNR = 10 log10(255^2 / 100) = 28.1308 dB.
  EXPECT_NEAR(s.psnr_db, 10.0 * std::log10(65025.0 / 100.0), 1e-9);
  EXPECT_NEAR(s.psnr_db, 28.1308, 1e-4);
}

TEST(ImageScores, IdenticalPicturesScoreTheCapOneAndZero) {
  const render::ImageRgba8 a = filled(32, 32, 77);
  render::ImageRgba8 b = a;
  for (std::size_t i = 3; i < b.data.size(); i += 4) b.data[i] = 0;  // alpha does not count
  const ImageScores s = score_image(b, a);
  EXPECT_EQ(s.psnr_db, kPsnrCapDb);
  EXPECT_NEAR(s.ssim, 1.0, 1e-9);
  EXPECT_NEAR(s.gmsd, 0.0, 1e-9);
}

// Two flat pictures: SSIM is its closed form (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1) with
// C1 = (0.01 * 255)^2 (the contrast and structure terms are 1: no variance), of the luma.
TEST(ImageScores, SsimOfTwoFlatPicturesIsTheClosedFormOfTheirLuma) {
  const render::ImageRgba8 truth = filled(64, 48, 100), shown = filled(64, 48, 110);
  const double c1 = (0.01 * 255) * (0.01 * 255);
  EXPECT_NEAR(score_image(shown, truth).ssim,
              (2.0 * 100 * 110 + c1) / (100.0 * 100 + 110.0 * 110 + c1), 1e-6);
}

// A colour change that keeps the luma (BT.601: 0.299 R + 0.587 G + 0.114 B) is seen by PSNR
// only: SSIM and GMSD are computed on the luma.
TEST(ImageScores, SsimAndGmsdSeeTheLumaOnly) {
  const render::ImageRgba8 truth = filled(64, 48, 100);
  render::ImageRgba8 shown = truth;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      shown.pixel(x, y)[0] = 110;  // 0.299 * 110 + 0.587 * 95 + 0.114 * 100 = 100.06
      shown.pixel(x, y)[1] = 95;
    }
  const ImageScores s = score_image(shown, truth);
  EXPECT_LT(s.psnr_db, 40.0);
  EXPECT_NEAR(s.ssim, 1.0, 1e-9);
  EXPECT_NEAR(s.gmsd, 0.0, 1e-9);
}

TEST(ImageScores, PsnrAgreesWithOpenCvsOwnOnRandomPictures) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> v(0, 255);
  render::ImageRgba8 a, b;
  a.allocate(80, 60);
  b.allocate(80, 60);
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    a.data[i] = static_cast<uint8_t>(v(rng));
    b.data[i] = static_cast<uint8_t>(i % 4 == 3 ? a.data[i] : v(rng));
  }
  // cv::PSNR over the four channels with alpha equal: its MSE is 3/4 of the colour channels'.
  const cv::Mat ma(60, 80, CV_8UC4, a.data.data()), mb(60, 80, CV_8UC4, b.data.data());
  const double mse4 = 65025.0 / std::pow(10.0, cv::PSNR(ma, mb) / 10.0);
  EXPECT_NEAR(score_image(a, b).psnr_db, psnr_from_mse(mse4 * 4.0 / 3.0), 1e-9);
  // Unrelated random pictures: SSIM near 0, GMSD well above a matched pair's.
  const ImageScores s = score_image(a, b);
  EXPECT_LT(std::abs(s.ssim), 0.05);
  EXPECT_GT(s.gmsd, 0.1);
}

TEST(ImageScores, AMaskScoresOnlyThePixelsItSelects) {
  const int w = 40, h = 20;
  render::ImageRgba8 truth = filled(w, h, 50), shown = filled(w, h, 50);
  std::vector<uint8_t> left(static_cast<std::size_t>(w * h), 0), right = left, none = left;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      if (x < w / 2) {
        left[i] = 1;
        for (int c = 0; c < 3; ++c) shown.row(y)[4 * x + c] = 70;  // off by 20 on the left half
      } else {
        right[i] = 255;
      }
    }
  EXPECT_NEAR(masked_psnr_db(shown, truth, left), 10.0 * std::log10(65025.0 / 400.0), 1e-9);
  EXPECT_EQ(masked_psnr_db(shown, truth, right), kPsnrCapDb);
  EXPECT_TRUE(std::isnan(masked_psnr_db(shown, truth, none)));
  // The whole picture: half the pixels off by 20, MSE 200.
  EXPECT_NEAR(score_image(shown, truth).psnr_db, 10.0 * std::log10(65025.0 / 200.0), 1e-9);
}

TEST(ImageScores, TheOnePassSplitAgreesWithThreeMasksAndTheMeanWeight) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> v(0, 255);
  const int w = 37, h = 23;
  render::ImageRgba8 a, b;
  a.allocate(w, h);
  b.allocate(w, h);
  for (std::size_t i = 0; i < a.data.size(); ++i) {
    a.data[i] = static_cast<uint8_t>(v(rng));
    b.data[i] = static_cast<uint8_t>(v(rng));
  }
  // Weights in a picture twice as wide (the eye's viewport in the stereo picture): stride 2 w.
  std::vector<uint8_t> weights(static_cast<std::size_t>(2 * w * h));
  std::vector<uint8_t> video(static_cast<std::size_t>(w * h)), blend = video, synth = video;
  double sum = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int r = v(rng);
      const uint8_t wt = r < 80 ? 0 : r < 160 ? 255 : static_cast<uint8_t>(1 + r % 254);
      weights[static_cast<std::size_t>(y * 2 * w + x)] = wt;
      const std::size_t i = static_cast<std::size_t>(y * w + x);
      synth[i] = wt == 0;
      video[i] = wt == 255;
      blend[i] = wt > 0 && wt < 255;
      sum += wt / 255.0;
    }
  const WeightSplit s = split_by_weight(a, b, weights.data(), static_cast<std::size_t>(2 * w));
  EXPECT_NEAR(s.psnr_video_db, masked_psnr_db(a, b, video), 1e-9);
  EXPECT_NEAR(s.psnr_blend_db, masked_psnr_db(a, b, blend), 1e-9);
  EXPECT_NEAR(s.psnr_synthetic_db, masked_psnr_db(a, b, synth), 1e-9);
  EXPECT_NEAR(s.video_fraction, sum / (w * h), 1e-12);
  // No video at all: its PSNR is NaN (nothing to score), the fraction 0.
  std::fill(weights.begin(), weights.end(), 0);
  const WeightSplit none = split_by_weight(a, b, weights.data(), static_cast<std::size_t>(2 * w));
  EXPECT_TRUE(std::isnan(none.psnr_video_db));
  EXPECT_TRUE(std::isnan(none.psnr_blend_db));
  EXPECT_EQ(none.video_fraction, 0.0);
  EXPECT_NEAR(none.psnr_synthetic_db, score_image(a, b).psnr_db, 1e-9);
}

TEST(ImageScores, PicturesOfDifferentSizesAreRefusedNamingBoth) {
  try {
    score_image(filled(4, 4, 0), filled(4, 5, 0));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("4x4 against 4x5"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hd::station
