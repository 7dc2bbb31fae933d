#pragma once
// The station's frame rate under `--rate-policy hold`: RateGovernor's divisor applied to the
// frame loop, each change reported when it happens, and the frames and missed deadlines at each
// rate kept for the summary (misses are counted against the rate in use, never hidden).

#include <array>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "render/loop/frame_loop.h"
#include "render/loop/rate_governor.h"

namespace hd::station {

/// Frames drawn at one rate, and how many of them missed that rate's deadline.
struct HeldRate {
  double rate_hz = 0.0;
  uint64_t frames = 0, missed_deadlines = 0;
};

class RateHolder {
 public:
  /// `hold` false: the display rate throughout (--rate-policy fixed); only the tally is kept.
  /// Changes are printed to `out`, timed from set_start()'s time.
  RateHolder(double display_hz, bool hold, std::FILE* out);
  void set_start(int64_t start_ns) { start_ns_ = start_ns; }

  /// The start report's line: the policy and the rates it may choose.
  std::string start_line() const;
  /// After each frame (outside the counted tick: it may print): tallies the frame at the rate
  /// it ran at, and sets the loop's divisor when the governor changes it.
  void after_frame(render::FrameLoop& loop, int64_t now_ns);

  /// The rates used, fastest first, with their frames and misses.
  std::vector<HeldRate> rates() const;
  uint64_t changes() const { return changes_; }
  bool holds() const { return governor_.has_value(); }

 private:
  double display_hz_;
  std::optional<render::RateGovernor> governor_;
  std::FILE* out_;
  int64_t start_ns_ = 0;
  uint64_t changes_ = 0;
  uint64_t missed_seen_ = 0;  // the loop's missed count at the previous frame
  static constexpr int kMaxDivisor = 4;
  std::array<HeldRate, kMaxDivisor + 1> by_divisor_{};  // [0] unused
};

}  // namespace hd::station
