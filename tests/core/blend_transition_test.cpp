// Blend weights, the transition policy and the marking data.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>

#include "core/blend_weights.h"
#include "core/marking.h"
#include "core/transition.h"

using namespace hd::core;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
double sinus(double w) {
  return (std::sin((w - 0.5) * M_PI) + 1) / 2;
}
}  // namespace

TEST(VideoWeight, LinearBandWithCorrectedSign) {
  EXPECT_EQ(video_weight(0, 40, 10), 1.0);
  EXPECT_EQ(video_weight(30, 40, 10), 1.0);
  EXPECT_DOUBLE_EQ(video_weight(35, 40, 10), 0.75);
  EXPECT_DOUBLE_EQ(video_weight(40, 40, 10), 0.5);
  EXPECT_DOUBLE_EQ(video_weight(45, 40, 10), 0.25);
  EXPECT_EQ(video_weight(50, 40, 10), 0.0);
  EXPECT_EQ(video_weight(kInf, 40, 10), 0.0);
}

TEST(VideoWeight, EpsZeroIsAHardSwitchAtMt) {
  EXPECT_EQ(video_weight(39.999, 40, 0), 1.0);
  EXPECT_EQ(video_weight(40, 40, 0), 1.0);
  EXPECT_EQ(video_weight(40.001, 40, 0), 0.0);
  EXPECT_EQ(video_weight(kInf, 40, 0), 0.0);
}

TEST(VideoWeight, NanAndBadParametersGiveSynthetic) {
  EXPECT_EQ(video_weight(NAN, 40, 10), 0.0);
  EXPECT_EQ(video_weight(10, NAN, 10), 0.0);
  EXPECT_EQ(video_weight(10, 40, NAN), 0.0);
  EXPECT_EQ(video_weight(10, 40, -1), 0.0);
  EXPECT_EQ(video_weight(10, 40, kInf), 0.0);
}

TEST(PixelWeight, RegionsOfThePaperWithCorrectedCorner) {
  const double W = 200, H = 100;
  // kappa = 0.5: inner box x',y' <= 0.5.
  EXPECT_EQ(pixel_weight(0.5, 100, 50, W, H), 1.0);  // centre
  EXPECT_EQ(pixel_weight(0.5, 150, 75, W, H), 1.0);  // x' = y' = 0.5, inner corner
  // Edge ramp: u = 170 -> x' = 0.7, w' = (1 - 0.7)/0.5 = 0.6.
  EXPECT_NEAR(pixel_weight(0.5, 170, 50, W, H), sinus(0.6), 1e-15);
  EXPECT_NEAR(pixel_weight(0.5, 30, 50, W, H), sinus(0.6), 1e-15);  // mirrored
  // Corner: x' = 0.7, y' = 0.8 -> w' = 1 - hypot(0.2, 0.3)/0.5 (centred at (0.5, 0.5)).
  EXPECT_NEAR(pixel_weight(0.5, 170, 90, W, H), sinus(1 - std::hypot(0.2, 0.3) / 0.5), 1e-12);
  // Far corner: w' < 0 is clamped to 0.
  EXPECT_EQ(pixel_weight(0.5, 200, 100, W, H), 0.0);
  EXPECT_EQ(pixel_weight(0.5, 0, 50, W, H), 0.0);  // on the border
}

TEST(PixelWeight, KappaZeroAndOneAndBadInput) {
  EXPECT_EQ(pixel_weight(0, 0, 0, 100, 100), 1.0);
  EXPECT_EQ(pixel_weight(0, 37, 99, 100, 100), 1.0);
  EXPECT_EQ(pixel_weight(1, 50, 50, 100, 100), 1.0);  // the DESIGN 7 jump: centre still 1
  EXPECT_NEAR(pixel_weight(1, 75, 50, 100, 100), sinus(0.5), 1e-15);
  EXPECT_EQ(pixel_weight(NAN, 50, 50, 100, 100), 0.0);
  EXPECT_EQ(pixel_weight(0.5, NAN, 50, 100, 100), 0.0);
  EXPECT_EQ(pixel_weight(0.5, 50, 50, 0, 100), 0.0);
  EXPECT_EQ(pixel_weight(0.5, -50, 50, 100, 100), 0.0);  // outside the frame
  EXPECT_EQ(pixel_weight(2.0, 50, 50, 100, 100), 1.0);   // kappa clamped to 1
}

RC_GTEST_PROP(PixelWeight, InUnitIntervalSymmetricAndNonIncreasingOutward, ()) {
  const double W = *rc::gen::inRange(2, 2000);
  const double H = *rc::gen::inRange(2, 2000);
  const double kappa = *rc::gen::inRange(0, 1001) / 1000.0;
  const double u = *rc::gen::inRange(0, 100001) / 100000.0 * W;
  const double v = *rc::gen::inRange(0, 100001) / 100000.0 * H;
  const double w = pixel_weight(kappa, u, v, W, H);
  RC_ASSERT(w >= 0.0 && w <= 1.0);
  RC_ASSERT(std::abs(w - pixel_weight(kappa, W - u, v, W, H)) <= 1e-12);
  RC_ASSERT(std::abs(w - pixel_weight(kappa, u, H - v, W, H)) <= 1e-12);
  // Moving toward the centre along the ray from it never lowers the weight.
  const double t = *rc::gen::inRange(0, 1001) / 1000.0;
  const double ui = W / 2 + t * (u - W / 2);
  const double vi = H / 2 + t * (v - H / 2);
  RC_ASSERT(pixel_weight(kappa, ui, vi, W, H) >= w - 1e-12);
  // Along each axis as well.
  RC_ASSERT(pixel_weight(kappa, ui, v, W, H) >= w - 1e-12);
  RC_ASSERT(pixel_weight(kappa, u, vi, W, H) >= w - 1e-12);
}

RC_GTEST_PROP(ContinuousPixelWeight, LipschitzInMAcrossTheWholeBand, ()) {
  // Sweep m finely through and beyond the band. With r = 1 - max(x', y') > 0 (a pixel centre is
  // never on the frame edge), |d w'2 / d kappa| <= (1 + sqrt 2) / r, the sinusoid's slope is
  // <= pi/2, d kappa'/dm = d strength/dm = 1/eps: so |dw/dm| <= L below. A jump anywhere in
  // the band (as the paper's rule has at m_t + eps) would break the bound.
  const double W = 640, H = 480, m_t = 40, eps = 10;
  const double u = *rc::gen::inRange(0, 640) + 0.5;
  const double v = *rc::gen::inRange(0, 480) + 0.5;
  const double r = 1 - std::max(std::abs(1 - 2 * u / W), std::abs(1 - 2 * v / H));
  const double L = (M_PI / 2) * (1 + std::sqrt(2.0)) / r / eps + 1 / eps;
  double prev = continuous_pixel_weight(video_weight(20, m_t, eps), u, v, W, H);
  RC_ASSERT(prev == 1.0);  // below the band: pure video
  const double dm = 0.01;
  for (int i = 1; i <= 4000; ++i) {
    const double m = 20 + i * dm;
    const double w = continuous_pixel_weight(video_weight(m, m_t, eps), u, v, W, H);
    RC_ASSERT(std::abs(w - prev) <= L * dm * 1.0001 + 1e-12);
    prev = w;
  }
  RC_ASSERT(prev == 0.0);  // above the band: pure synthetic
}

TEST(ContinuousPixelWeight, PaperRuleJumpsButOursDoesNot) {
  // Just inside the band's top (w_video -> 0+) the paper's w2 at the centre is 1 and drops to 0
  // beyond the band; the continuous rule goes to 0.
  const double w_small = video_weight(49.999, 40, 10);
  EXPECT_EQ(pixel_weight(1 - w_small, 320, 240, 640, 480), 1.0);
  EXPECT_LT(continuous_pixel_weight(w_small, 320, 240, 640, 480), 1e-3);
  EXPECT_EQ(continuous_pixel_weight(1.0, 0.5, 0.5, 640, 480), 1.0);
  EXPECT_EQ(continuous_pixel_weight(NAN, 320, 240, 640, 480), 0.0);
}

TEST(Transition, AbruptWithHysteresis) {
  Transition t({TransitionMode::kAbrupt, 40, 10, 5, 0.15});
  EXPECT_EQ(t.update(30, 0.01).variant, Variant::kVideo);
  EXPECT_EQ(t.update(44, 0.01).variant, Variant::kVideo);  // inside m_t + h
  EXPECT_EQ(t.update(45.5, 0.01).variant, Variant::kSynthetic);
  EXPECT_EQ(t.update(38, 0.01).variant, Variant::kSynthetic);  // above m_t - h
  const auto s = t.update(34.9, 0.01);
  EXPECT_EQ(s.variant, Variant::kVideo);
  EXPECT_EQ(s.w_video, 1.0);
  EXPECT_EQ(s.kappa, 0.0);
  EXPECT_EQ(t.update(NAN, 0.01).variant, Variant::kSynthetic);
  EXPECT_EQ(t.update(kInf, 0.01).variant, Variant::kSynthetic);
}

TEST(Transition, GlobalBlendFollowsVideoWeightWithoutSmoothing) {
  Transition t({TransitionMode::kGlobalBlend, 40, 10, 5, 0.0});
  auto s = t.update(45, 0.01);
  EXPECT_DOUBLE_EQ(s.w_video, 0.25);
  EXPECT_DOUBLE_EQ(s.kappa, 0.75);
  EXPECT_EQ(s.variant, Variant::kHybrid);
  EXPECT_EQ(t.update(kInf, 0.01).variant, Variant::kSynthetic);
  EXPECT_EQ(t.update(0, 0.01).variant, Variant::kVideo);
  EXPECT_EQ(t.update(NAN, 0.01).w_video, 0.0);
}

TEST(Transition, FirstOrderSmoothingMatchesTheExponential) {
  const double tau = 0.15;
  Transition t({TransitionMode::kPerPixel, 40, 10, 5, tau});
  EXPECT_EQ(t.update(0, 0.01).w_video, 1.0);  // first update takes the target
  // Step to m = inf (target 0): after n steps of dt, w = exp(-n dt / tau).
  double w = 0;
  for (int n = 1; n <= 10; ++n) {
    w = t.update(kInf, 0.01).w_video;
    EXPECT_NEAR(w, std::exp(-n * 0.01 / tau), 1e-12);
  }
  EXPECT_EQ(t.update(kInf, NAN).w_video, w);   // NaN dt holds
  EXPECT_EQ(t.update(kInf, -1.0).w_video, w);  // negative dt holds
  // It snaps to exactly synthetic on the first step that lands within kTransitionSnap of the
  // target: exp(-n dt / tau) < 1/512 first for n = ceil(15 ln 512) = 94 steps after the change.
  {
    Transition u({TransitionMode::kPerPixel, 40, 10, 5, tau});
    u.update(0, 0.01);
    TransitionState step{};
    for (int n = 1; n <= 93; ++n) step = u.update(kInf, 0.01);
    EXPECT_NEAR(step.w_video, std::exp(-93 * 0.01 / tau), 1e-12);
    EXPECT_EQ(step.variant, Variant::kHybrid);
    step = u.update(kInf, 0.01);
    EXPECT_EQ(step.w_video, 0.0);
    EXPECT_EQ(step.variant, Variant::kSynthetic);
  }
  TransitionState s{};
  for (int n = 0; n < 1000; ++n) s = t.update(kInf, 0.01);
  EXPECT_EQ(s.w_video, 0.0);
  EXPECT_EQ(s.variant, Variant::kSynthetic);
  t.reset();
  EXPECT_EQ(t.update(0, 0.01).w_video, 1.0);
}

TEST(Marking, SanitizedClampsEveryNumber) {
  MarkingParams p;
  p.checker_cell_px = 0;
  p.checker_contrast = 3;
  p.synthetic_desaturation = NAN;
  p.frame_width_px = -4;
  const MarkingParams q = p.sanitized();
  EXPECT_EQ(q.checker_cell_px, 1);
  EXPECT_EQ(q.checker_contrast, 1.0);
  EXPECT_EQ(q.synthetic_desaturation, MarkingParams{}.synthetic_desaturation);
  EXPECT_EQ(q.frame_width_px, 0);
  // Every variant has its own frame colour.
  const auto& a = q.frame_colour(Variant::kVideo);
  const auto& b = q.frame_colour(Variant::kSynthetic);
  EXPECT_FALSE(a.r == b.r && a.g == b.g && a.b == b.b);
}
