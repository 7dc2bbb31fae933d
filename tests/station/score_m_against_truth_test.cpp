// m against the truth: Spearman's rho and the break-even m on series with known answers.
#include "station/score/m_against_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hd::station {
namespace {

TEST(MAgainstTruth, SpearmanIsOneForAnyIncreasingRelationAndMinusOneReversed) {
  const std::vector<double> x = {1, 2, 3, 4, 5, 6};
  EXPECT_NEAR(spearman_rho(x, {1, 4, 9, 16, 25, 36}), 1.0, 1e-12);
  EXPECT_NEAR(spearman_rho(x, {6, 5, 4, 3, 2, 1}), -1.0, 1e-12);
  EXPECT_TRUE(std::isnan(spearman_rho({1, 2}, {1, 2})));
  EXPECT_TRUE(std::isnan(spearman_rho(x, {3, 3, 3, 3, 3, 3})));
}

TEST(MAgainstTruth, SpearmanGivesTiesTheirMeanRank) {
  // x ranks 1, 2.5, 2.5, 4; y ranks 1, 2, 3, 4: rho = Pearson of the ranks = 0.9486833 (by hand:
  // sum dx dy = 4.5, sum dx^2 = 4.5, sum dy^2 = 5, 4.5 / sqrt(22.5)).
  EXPECT_NEAR(spearman_rho({10, 20, 20, 30}, {1, 2, 3, 4}), 4.5 / std::sqrt(22.5), 1e-12);
}

TEST(MAgainstTruth, TheBreakEvenIsWhereTheVideoViewFallsBelowTheModel) {
  // Video PSNR 40 - 0.1 m, model 30 dB: equal at m = 100. m uniform on 0..199.5.
  std::vector<MSample> s;
  for (int i = 0; i < 400; ++i) {
    const double m = 0.5 * i;
    s.push_back({m, 40.0 - 0.1 * m, 30.0});
  }
  s.push_back({NAN, 10.0, 10.0});  // no m: left out
  const MAgainstTruth r = m_against_truth(s, 10);
  EXPECT_EQ(r.samples, 400u);
  EXPECT_NEAR(r.break_even_m, 100.0, 1e-9);  // linear in each group's mean: exact
  EXPECT_NEAR(r.spearman, 1.0, 1e-12);       // the error grows with m, strictly
}

TEST(MAgainstTruth, NoCrossingInTheRangeGivesNoBreakEven) {
  std::vector<MSample> s;
  for (int i = 0; i < 50; ++i) s.push_back({double(i), 45.0 - 0.01 * i, 30.0});
  EXPECT_TRUE(std::isnan(m_against_truth(s).break_even_m));
}

}  // namespace
}  // namespace hd::station
