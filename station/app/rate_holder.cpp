// RateHolder: the governor's divisor into the frame loop, reported and tallied.
#include "station/app/rate_holder.h"

#include <cinttypes>

namespace hd::station {

RateHolder::RateHolder(double display_hz, bool hold, std::FILE* out)
    : display_hz_(display_hz), out_(out) {
  if (hold) {
    render::RateGovernorConfig c;
    c.display_hz = display_hz;
    c.max_divisor = kMaxDivisor;
    governor_.emplace(c);
  }
  for (int d = 1; d <= kMaxDivisor; ++d)
    by_divisor_[static_cast<std::size_t>(d)].rate_hz = display_hz / d;
}

std::string RateHolder::start_line() const {
  char text[400];
  if (!governor_) {
    std::snprintf(text, sizeof text,
                  "%.1f Hz, fixed (--rate-policy fixed): every frame that misses it is counted",
                  display_hz_);
  } else {
    const render::RateGovernorConfig& c = governor_->config();
    std::snprintf(text, sizeof text,
                  "%.1f Hz display; held (--rate-policy hold): the fastest of %.1f / %.1f / "
                  "%.1f / %.1f Hz whose frames fit %.0f %% of their period (%d of %d frames over "
                  "it slow it down; %.0f s of fitting a faster one speeds it up), each change "
                  "reported",
                  display_hz_, display_hz_, display_hz_ / 2, display_hz_ / 3, display_hz_ / 4,
                  100.0 * c.headroom, render::RateGovernor::kOverrunsToSlow,
                  render::RateGovernor::kWindow, 1e-9 * double(c.recover_ns));
  }
  return text;
}

void RateHolder::after_frame(render::FrameLoop& loop, int64_t now_ns) {
  HeldRate& r = by_divisor_[static_cast<std::size_t>(loop.divisor())];
  ++r.frames;
  const uint64_t missed = loop.missed_deadlines();
  r.missed_deadlines += missed - missed_seen_;
  missed_seen_ = missed;
  if (!governor_) return;
  const int before = governor_->divisor();
  const std::optional<int> d = governor_->observe(loop.last_work_ns(), now_ns);
  if (!d) return;
  loop.set_divisor(*d);
  ++changes_;
  std::fprintf(out_,
               "  [%6.1f s] rate %.1f Hz -> %.1f Hz: the last frame's work took %.1f ms, the "
               "period at %.1f Hz is %.1f ms\n",
               1e-9 * double(now_ns - start_ns_), display_hz_ / before, display_hz_ / *d,
               1e-6 * double(loop.last_work_ns()), display_hz_ / before,
               1e3 / (display_hz_ / before));
  std::fflush(out_);
}

std::vector<HeldRate> RateHolder::rates() const {
  std::vector<HeldRate> used;
  for (int d = 1; d <= kMaxDivisor; ++d)
    if (by_divisor_[static_cast<std::size_t>(d)].frames > 0)
      used.push_back(by_divisor_[static_cast<std::size_t>(d)]);
  return used;
}

}  // namespace hd::station
