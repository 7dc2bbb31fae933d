// Replaying candidate transitions over recorded frames finds the threshold a closed form gives,
// and each candidate's scores are what its own core::Transition would have shown.
#include "station/score/transition_tuning.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "station/score/image_scores.h"

namespace hd::station {
namespace {

constexpr int kW = 32, kH = 24;

render::ImageRgba8 flat(int value) {
  render::ImageRgba8 im;
  im.allocate(kW, kH);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      uint8_t* p = im.pixel(x, y);
      p[0] = p[1] = p[2] = static_cast<uint8_t>(value);
      p[3] = 255;
    }
  return im;
}

// A frame whose model is off by 10 levels everywhere and whose video is off by m / 3 levels
// (video covering the whole picture): the video is the better picture exactly while m < 30.
BlendErrorModel frame_at(double m, std::vector<float>& positions) {
  positions.assign(2 * kW * kH, 0.0f);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      positions[2 * (y * kW + x)] = x + 0.5f;
      positions[2 * (y * kW + x) + 1] = y + 0.5f;
    }
  BlendErrorModel e;
  e.build(flat(100), flat(110), flat(100 + static_cast<int>(std::lround(m / 3.0))),
          positions.data(), kW, kH);
  return e;
}

// m rising from 0 to 90 px, then falling back: without hysteresis or lag the best abrupt
// threshold is the break-even m = 30 px (ties at m = 30 itself: 30 / 3 = 10 levels both).
TEST(TransitionTuning, TheBestAbruptThresholdIsTheBreakEven) {
  core::TransitionParams base;
  base.hysteresis = 0.0;
  base.time_constant_s = 0.0;
  std::vector<TuningCandidate> grid;
  for (double m_t : {10.0, 20.0, 25.0, 30.0, 35.0, 40.0, 60.0})
    grid.push_back({core::TransitionMode::kAbrupt, m_t, 0.0});
  TransitionTuner tuner(grid, base);
  std::vector<float> positions;
  for (int k = 0; k <= 180; ++k) {
    const double m = k <= 90 ? k : 180 - k;
    const BlendErrorModel e = frame_at(m, positions);
    const BlendErrorModel* eyes[] = {&e};
    tuner.add_frame(m, 0.01, 1.0, eyes);
  }
  const TuningResult best = tuner.best(core::TransitionMode::kAbrupt);
  EXPECT_DOUBLE_EQ(best.candidate.m_t, 30.0);
  // Every other threshold shows the worse picture in some frames.
  for (const TuningResult& r : tuner.results()) {
    if (r.candidate.m_t != 30.0) {
      EXPECT_LT(r.psnr_mean_db, best.psnr_mean_db) << r.candidate.m_t;
    }
  }
  // m_t = 30 shows video in 61 of 181 frames (m = 0..30 on the way up and down).
  EXPECT_NEAR(best.video_share, 61.0 / 181.0, 1e-12);
}

// Each candidate's trace is its own core::Transition's weight scored through the frame's model:
// lag, eps and the age cap included.
TEST(TransitionTuning, ACandidatesScoresFollowItsOwnTransition) {
  core::TransitionParams base;  // the station's hysteresis and 0.15 s lag
  const TuningCandidate c{core::TransitionMode::kPerPixel, 40.0, 10.0};
  TransitionTuner tuner({c, {core::TransitionMode::kGlobalBlend, 20.0, 5.0}}, base);
  core::TransitionParams p = base;
  p.mode = c.mode;
  p.m_t = c.m_t;
  p.eps = c.eps;
  core::Transition reference(p);
  std::vector<double> expected;
  std::vector<float> positions;
  for (int k = 0; k < 120; ++k) {
    const double m = 25.0 + 30.0 * std::sin(0.05 * k);
    const double w_cap = k > 100 ? 0.3 : 1.0;  // the video ages past its bound at the end
    const BlendErrorModel e = frame_at(m, positions);
    const BlendErrorModel* eyes[] = {&e, &e};
    tuner.add_frame(m, 1.0 / 90.0, w_cap, eyes);
    const double w = reference.update(m, 1.0 / 90.0, w_cap).w_video;
    expected.push_back(e.psnr_db(core::TransitionMode::kPerPixel, w));
    expected.push_back(e.psnr_db(core::TransitionMode::kPerPixel, w));
  }
  ASSERT_EQ(tuner.trace(0).size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_DOUBLE_EQ(tuner.trace(0)[i], expected[i]) << i;
  // The other candidate (another m_t) saw other pictures.
  EXPECT_NE(tuner.trace(1), tuner.trace(0));
}

TEST(TransitionTuning, TheDefaultGridCoversEveryModeAndThePapersValues) {
  const std::vector<TuningCandidate> grid = TransitionTuner::default_grid();
  bool abrupt = false, global = false, paper = false;
  for (const TuningCandidate& c : grid) {
    abrupt |= c.mode == core::TransitionMode::kAbrupt;
    global |= c.mode == core::TransitionMode::kGlobalBlend;
    paper |= c.mode == core::TransitionMode::kPerPixel && c.m_t == 40.0 && c.eps == 10.0;
  }
  EXPECT_TRUE(abrupt && global && paper);
  TransitionTuner tuner({{core::TransitionMode::kAbrupt, 40.0, 0.0}}, {});
  EXPECT_THROW(tuner.best(core::TransitionMode::kPerPixel), std::logic_error);
}

}  // namespace
}  // namespace hd::station
