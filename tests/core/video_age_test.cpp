// Time as an input of the decision (core/video_age.h): the default bound, m extended by time,
// the age cap on the video weight and the transition held under it.
#include "core/video_age.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/marking.h"
#include "core/transition.h"

namespace hd::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(VideoAge, DefaultIsThreeFramePeriodsButAtLeast100MsPlusTheKnownDelay) {
  EXPECT_DOUBLE_EQ(default_max_video_age_s(25.0), 0.12);  // the fake GigE camera's rate
  EXPECT_DOUBLE_EQ(default_max_video_age_s(30.0), 0.1);
  EXPECT_DOUBLE_EQ(default_max_video_age_s(60.0), 0.1);
  EXPECT_DOUBLE_EQ(default_max_video_age_s(10.0), 0.3);
  EXPECT_DOUBLE_EQ(default_max_video_age_s(0.0), 0.1);
  EXPECT_DOUBLE_EQ(default_max_video_age_s(NAN), 0.1);
  EXPECT_DOUBLE_EQ(default_max_video_age_s(60.0, 0.08), 0.18);
  EXPECT_DOUBLE_EQ(default_max_video_age_s(60.0, -1.0), 0.1);
}

TEST(VideoAge, FadeIsTheTransitionsTimeConstantButAtMostHalfTheBound) {
  EXPECT_DOUBLE_EQ(video_age_fade_s(0.1, 0.15), 0.05);
  EXPECT_DOUBLE_EQ(video_age_fade_s(1.0, 0.15), 0.15);
  EXPECT_DOUBLE_EQ(video_age_fade_s(0.1, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(video_age_fade_s(0.1, NAN), 0.0);
}

TEST(VideoAge, MIsInfiniteOnceTheFrameIsTooOldOrTheSourceStopsStreaming) {
  EXPECT_EQ(time_extended_m(12.5, true, 0.0, 0.1), 12.5);
  EXPECT_EQ(time_extended_m(12.5, true, 0.0999, 0.1), 12.5);
  EXPECT_EQ(time_extended_m(12.5, true, -0.002, 0.1), 12.5);  // stamped just after display
  EXPECT_EQ(time_extended_m(12.5, true, 0.1, 0.1), kInf);
  EXPECT_EQ(time_extended_m(12.5, true, 4.9, 0.1), kInf);
  EXPECT_EQ(time_extended_m(12.5, false, 0.01, 0.1), kInf);
  EXPECT_EQ(time_extended_m(12.5, true, NAN, 0.1), kInf);
  EXPECT_TRUE(std::isnan(time_extended_m(NAN, true, 0.01, 0.1)));
}

TEST(VideoAge, CapIsOneUpToTheBoundThenFallsLinearlyToZeroOverTheFade) {
  EXPECT_EQ(video_weight_cap(0.0, 0.1, 0.05), 1.0);
  EXPECT_EQ(video_weight_cap(0.1, 0.1, 0.05), 1.0);
  EXPECT_NEAR(video_weight_cap(0.1125, 0.1, 0.05), 0.75, 1e-12);
  EXPECT_NEAR(video_weight_cap(0.125, 0.1, 0.05), 0.5, 1e-12);
  EXPECT_NEAR(video_weight_cap(0.15, 0.1, 0.05), 0.0, 1e-12);
  EXPECT_EQ(video_weight_cap(3.0, 0.1, 0.05), 0.0);
  EXPECT_EQ(video_weight_cap(0.1001, 0.1, 0.0), 0.0);
  EXPECT_EQ(video_weight_cap(NAN, 0.1, 0.05), 0.0);
}

TEST(VideoAge, AgeOfAStampAndNoStamp) {
  EXPECT_DOUBLE_EQ(age_s(1'000'000'000, 1'250'000'000), 0.25);
  EXPECT_TRUE(std::isnan(age_s(0, 1'250'000'000)));
}

// A camera at m = 0 going stale at 90 Hz: the blend's weight stays 1 while the frame is young,
// then follows the cap down (not the 0.15 s lag, which would keep a frozen frame ~0.9 s), and
// no frame older than max + fade is drawn with any weight.
TEST(VideoAge, TransitionUnderTheCapLeavesAStaleFrameWithinTheFade) {
  TransitionParams p;
  p.mode = TransitionMode::kGlobalBlend;
  p.time_constant_s = 0.15;
  Transition t(p);
  const double max_age = 0.1, fade = video_age_fade_s(max_age, p.time_constant_s), dt = 1.0 / 90;
  double last_shown_age = 0.0;
  for (int k = 0; k < 60; ++k) {
    const double age = 0.02 + k * dt;
    const TransitionState s = t.update(time_extended_m(0.0, true, age, max_age), dt,
                                       video_weight_cap(age, max_age, fade));
    if (age <= max_age) {
      EXPECT_EQ(s.variant, Variant::kVideo) << age;
    }
    if (s.w_video > 0.0) last_shown_age = age;
    EXPECT_LE(s.w_video, video_weight_cap(age, max_age, fade)) << age;
  }
  EXPECT_GT(last_shown_age, max_age);  // it faded, it did not cut
  EXPECT_LT(last_shown_age, max_age + fade);
  // Fresh video again: it fades in from 0 with the lag (the cap lowered the lag's state).
  const TransitionState back = t.update(0.0, dt, 1.0);
  EXPECT_EQ(back.variant, Variant::kHybrid);
  EXPECT_NEAR(back.w_video, 1.0 - std::exp(-dt / p.time_constant_s), 1e-12);
}

TEST(VideoAge, AbruptModeSwitchesAtTheBoundWithoutFading) {
  TransitionParams p;
  p.mode = TransitionMode::kAbrupt;
  Transition t(p);
  EXPECT_EQ(t.update(0.0, 0.01, 1.0).w_video, 1.0);
  EXPECT_EQ(t.update(0.0, 0.01, 0.99).w_video, 0.0);
  EXPECT_EQ(t.update(kInf, 0.01, 1.0).w_video, 0.0);
  EXPECT_EQ(t.update(0.0, 0.01, 1.0).w_video, 1.0);
}

TEST(VideoAge, ACapOfOneOrNanChangesNothing) {
  TransitionParams p;
  Transition a(p), b(p), c(p);
  for (int k = 0; k < 50; ++k) {
    const double m = 20.0 + 40.0 * std::sin(0.2 * k);
    const double wa = a.update(m, 0.011).w_video;
    EXPECT_EQ(b.update(m, 0.011, 1.0).w_video, wa);
    EXPECT_EQ(c.update(m, 0.011, NAN).w_video, wa);
  }
}

// The staleness cue's parameters: none for fresh data or an unknown age, linear in between,
// the checker contrast growing, nothing for the unmarked style.
TEST(StalenessCue, FadeGrowsLinearlyWithModelAgeAndIsZeroWhenFresh) {
  MarkingParams m;  // desaturate; fresh 2 s, full 10 s, fade 0.6
  EXPECT_EQ(m.for_ages(1999.0, false).synthetic_fade, 0.0);
  EXPECT_EQ(m.for_ages(NAN, false).synthetic_fade, 0.0);
  EXPECT_NEAR(m.for_ages(6000.0, false).synthetic_fade, 0.3, 1e-12);
  EXPECT_NEAR(m.for_ages(10000.0, false).synthetic_fade, 0.6, 1e-12);
  EXPECT_NEAR(m.for_ages(60000.0, false).synthetic_fade, 0.6, 1e-12);
  EXPECT_TRUE(m.for_ages(0.0, true).video_stale);
  EXPECT_FALSE(m.for_ages(0.0, false).video_stale);
  m.style = MarkingStyle::kChecker;
  EXPECT_DOUBLE_EQ(m.for_ages(1000.0, false).checker_contrast, 0.25);
  EXPECT_NEAR(m.for_ages(6000.0, false).checker_contrast, 0.25 + 0.5 * 0.35, 1e-12);
  m.style = MarkingStyle::kNone;
  EXPECT_EQ(m.for_ages(60000.0, true).synthetic_fade, 0.0);
  EXPECT_FALSE(m.for_ages(60000.0, true).video_stale);
}

}  // namespace
}  // namespace hd::core
