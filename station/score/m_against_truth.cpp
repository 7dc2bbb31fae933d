#include "station/score/m_against_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace hd::station {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Ranks 1..n, ties given the mean of the ranks they span.
std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<std::size_t> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return v[i] < v[j]; });
  std::vector<double> r(v.size());
  for (std::size_t i = 0; i < order.size();) {
    std::size_t j = i;
    while (j + 1 < order.size() && v[order[j + 1]] == v[order[i]]) ++j;
    const double mean_rank = 0.5 * static_cast<double>(i + j) + 1.0;
    for (std::size_t k = i; k <= j; ++k) r[order[k]] = mean_rank;
    i = j + 1;
  }
  return r;
}

}  // namespace

double spearman_rho(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.size() < 3) return kNaN;
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double n = static_cast<double>(a.size());
  const double mean = (n + 1.0) / 2.0;
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - mean) * (rb[i] - mean);
    saa += (ra[i] - mean) * (ra[i] - mean);
    sbb += (rb[i] - mean) * (rb[i] - mean);
  }
  if (saa == 0.0 || sbb == 0.0) return kNaN;
  return sab / std::sqrt(saa * sbb);
}

MAgainstTruth m_against_truth(std::vector<MSample> samples, int bins) {
  samples.erase(std::remove_if(samples.begin(), samples.end(),
                               [](const MSample& s) {
                                 return !std::isfinite(s.m) || !std::isfinite(s.video_psnr_db) ||
                                        !std::isfinite(s.synthetic_psnr_db);
                               }),
                samples.end());
  MAgainstTruth out;
  out.samples = samples.size();
  std::vector<double> m, error;
  for (const MSample& s : samples) {
    m.push_back(s.m);
    error.push_back(-s.video_psnr_db);  // MSE's ranks
  }
  out.spearman = spearman_rho(m, error);
  out.break_even_m = kNaN;
  if (samples.empty() || bins < 2) return out;
  std::sort(samples.begin(), samples.end(),
            [](const MSample& a, const MSample& b) { return a.m < b.m; });
  const std::size_t groups = std::min<std::size_t>(static_cast<std::size_t>(bins), samples.size());
  std::vector<double> group_m(groups), group_diff(groups);  // video - model PSNR
  for (std::size_t g = 0; g < groups; ++g) {
    const std::size_t begin = g * samples.size() / groups, end = (g + 1) * samples.size() / groups;
    double sm = 0.0, sd = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      sm += samples[i].m;
      sd += samples[i].video_psnr_db - samples[i].synthetic_psnr_db;
    }
    group_m[g] = sm / static_cast<double>(end - begin);
    group_diff[g] = sd / static_cast<double>(end - begin);
  }
  for (std::size_t g = 1; g < groups; ++g)
    if (group_diff[g - 1] >= 0.0 && group_diff[g] < 0.0) {
      const double f = group_diff[g - 1] / (group_diff[g - 1] - group_diff[g]);
      out.break_even_m = group_m[g - 1] + f * (group_m[g] - group_m[g - 1]);
      break;
    }
  return out;
}

}  // namespace hd::station
