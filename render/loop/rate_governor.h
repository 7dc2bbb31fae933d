#pragma once
// The frame rate the station can hold: a divisor of the display's rate (90, 45, 30, 22.5 Hz),
// chosen from how long each frame's work takes, the way VR runtimes drop an application that
// misses frames to half rate. Pure: durations in, a divisor out.

#include <array>
#include <cstdint>
#include <optional>

namespace hd::render {

struct RateGovernorConfig {
  double display_hz = 90.0;
  /// The slowest rate is display_hz / max_divisor: below about 20 Hz the picture judders more
  /// than a missed frame costs.
  int max_divisor = 4;
  /// A rate is held when a frame's work fits in this share of its period; the rest absorbs a
  /// scheduler's jitter (on a 2-core machine with the remote site beside it, a few ms).
  double headroom = 0.85;
  /// A faster rate is taken again only once every frame's work has fitted it for this long: a
  /// rate that changes every few frames judders worse than either rate.
  int64_t recover_ns = 3'000'000'000;
};

/// Slowing down is quick, speeding up slow. After each frame observe() takes the time its work
/// took. Once 3 of the last kWindow frames overran headroom x the period in use, the divisor
/// becomes the smallest whose period holds the window's third-longest work (the divisor
/// never rises by more than what the work needs). It falls by one once every frame's work has
/// fitted headroom x the faster period for recover_ns and the last change is as old.
class RateGovernor {
 public:
  static constexpr int kWindow = 8;
  static constexpr int kOverrunsToSlow = 3;

  /// std::invalid_argument for a display rate outside (0, 1000] Hz, a max_divisor below 1, a
  /// headroom outside (0, 1] or a negative recover_ns.
  explicit RateGovernor(RateGovernorConfig config);

  /// A frame's work took `work_ns`, ending at `now_ns`. The new divisor when it changed.
  std::optional<int> observe(int64_t work_ns, int64_t now_ns);

  int divisor() const { return divisor_; }
  double rate_hz() const { return config_.display_hz / divisor_; }
  const RateGovernorConfig& config() const { return config_; }

 private:
  int64_t fit_ns(int divisor) const;  // headroom x the period at `divisor`

  RateGovernorConfig config_;
  int64_t display_period_ns_;
  int divisor_ = 1;
  std::array<int64_t, kWindow> window_{};
  int count_ = 0, next_ = 0;
  int64_t last_change_ns_ = 0;
  int64_t last_too_slow_for_faster_ns_ = 0;  // a frame's work did not fit the faster rate
  bool started_ = false;
};

}  // namespace hd::render
