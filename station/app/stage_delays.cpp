// StageSeries and StageDelays: sliding and run-long p50s of each stage's time since capture.
#include "station/app/stage_delays.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace hd::station {

void StageSeries::add(double ms, int64_t now_ns) {
  if (!(ms >= 0.0)) return;
  recent_ms_[next_] = ms;
  recent_at_ns_[next_] = now_ns;
  next_ = (next_ + 1) % kRecent;
  if (histogram_.empty()) histogram_.assign(kBins, 0);
  const auto bin = static_cast<std::size_t>(std::min(ms / kBinMs, double(kBins - 1)));
  ++histogram_[bin];
  ++count_;
}

double StageSeries::p50_last_second(int64_t now_ns) const {
  std::array<double, kRecent> in{};
  std::size_t n = 0;
  const std::size_t filled = std::min<uint64_t>(count_, kRecent);
  for (std::size_t i = 0; i < filled; ++i)
    if (recent_at_ns_[i] <= now_ns && now_ns - recent_at_ns_[i] < 1'000'000'000)
      in[n++] = recent_ms_[i];
  if (n == 0) return NAN;
  std::nth_element(in.begin(), in.begin() + std::ptrdiff_t(n / 2), in.begin() + std::ptrdiff_t(n));
  return in[n / 2];
}

double StageSeries::p50_run() const {
  if (count_ == 0) return NAN;
  const uint64_t half = count_ / 2;  // the sample at index count / 2, as p50_last_second takes
  uint64_t seen = 0;
  for (std::size_t b = 0; b < kBins; ++b) {
    seen += histogram_[b];
    if (seen > half) return (double(b) + 0.5) * kBinMs;
  }
  return double(kBins) * kBinMs;
}

StageDelays::StageDelays(std::vector<std::string> names, std::vector<std::string> short_names)
    : names_(std::move(names)), short_names_(std::move(short_names)), series_(names_.size()) {}

StageDelays StageDelays::video() {
  return StageDelays({"capture", "encoded", "sent", "received", "decoded", "on screen"},
                     {"cap", "enc", "sent", "recv", "dec", "shown"});
}

StageDelays StageDelays::model() {
  return StageDelays({"capture", "reconstructed", "in the model", "on screen"},
                     {"cap", "recon", "model", "shown"});
}

std::string StageDelays::hud_text(int64_t now_ns) const {
  std::string text;
  char part[64];
  for (std::size_t i = 1; i < names_.size(); ++i) {
    const double ms = series_[i].p50_last_second(now_ns);
    if (std::isnan(ms)) continue;
    std::snprintf(part, sizeof part, "%s%s %.1f", text.empty() ? "" : " > ",
                  short_names_[i].c_str(), ms);
    text += part;
  }
  return text.empty() ? text : text + " ms";
}

}  // namespace hd::station
