// RateGovernor: the divisor of the display rate from the frames' work times.
#include "render/loop/rate_governor.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>

namespace hd::render {

RateGovernor::RateGovernor(RateGovernorConfig config) : config_(config), display_period_ns_(0) {
  if (!std::isfinite(config.display_hz) || config.display_hz <= 0.0 || config.display_hz > 1000.0)
    throw std::invalid_argument("rate governor: display_hz must be in (0, 1000], got " +
                                std::to_string(config.display_hz));
  if (config.max_divisor < 1)
    throw std::invalid_argument("rate governor: max_divisor must be >= 1, got " +
                                std::to_string(config.max_divisor));
  if (!(config.headroom > 0.0 && config.headroom <= 1.0))
    throw std::invalid_argument("rate governor: headroom must be in (0, 1], got " +
                                std::to_string(config.headroom));
  if (config.recover_ns < 0) throw std::invalid_argument("rate governor: recover_ns must be >= 0");
  display_period_ns_ = static_cast<int64_t>(std::llround(1e9 / config.display_hz));
}

int64_t RateGovernor::fit_ns(int divisor) const {
  return static_cast<int64_t>(config_.headroom * double(display_period_ns_ * divisor));
}

std::optional<int> RateGovernor::observe(int64_t work_ns, int64_t now_ns) {
  if (!started_) {
    started_ = true;
    last_change_ns_ = last_too_slow_for_faster_ns_ = now_ns;
  }
  window_[static_cast<std::size_t>(next_)] = work_ns;
  next_ = (next_ + 1) % kWindow;
  count_ = std::min(count_ + 1, kWindow);
  if (divisor_ > 1 && work_ns > fit_ns(divisor_ - 1)) last_too_slow_for_faster_ns_ = now_ns;

  const auto begin = window_.begin(), end = window_.begin() + count_;
  const auto overruns = std::count_if(begin, end, [&](int64_t w) { return w > fit_ns(divisor_); });
  int next = divisor_;
  if (overruns >= kOverrunsToSlow && divisor_ < config_.max_divisor) {
    std::array<int64_t, kWindow> sorted = window_;  // unfilled slots sort last
    for (int i = count_; i < kWindow; ++i) sorted[static_cast<std::size_t>(i)] = INT64_MIN;
    std::sort(sorted.begin(), sorted.end(), std::greater<>());
    const int64_t third_longest = sorted[kOverrunsToSlow - 1];
    next = divisor_ + 1;
    while (next < config_.max_divisor && third_longest > fit_ns(next)) ++next;
  } else if (divisor_ > 1 && now_ns - last_too_slow_for_faster_ns_ >= config_.recover_ns &&
             now_ns - last_change_ns_ >= config_.recover_ns) {
    next = divisor_ - 1;
  }
  if (next == divisor_) return std::nullopt;
  divisor_ = next;
  // The window's frames were timed at the old rate's slots; the new one starts afresh.
  count_ = next_ = 0;
  last_change_ns_ = last_too_slow_for_faster_ns_ = now_ns;
  return divisor_;
}

}  // namespace hd::render
