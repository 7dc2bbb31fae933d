#pragma once
// The time source the frame loop paces itself with (a seam so tests can run on a fake clock).

#include <cstdint>

namespace hd::render {

class LoopClock {
 public:
  virtual ~LoopClock() = default;
  virtual int64_t now_ns() = 0;
  /// Sleeps until the absolute CLOCK_MONOTONIC time `t_ns` (returns at once if it has passed).
  virtual void sleep_until_ns(int64_t t_ns) = 0;
};

/// CLOCK_MONOTONIC with clock_nanosleep(TIMER_ABSTIME): absolute deadlines do not drift by the
/// time spent computing the sleep, and EINTR resumes toward the same deadline.
class MonotonicLoopClock final : public LoopClock {
 public:
  int64_t now_ns() override;
  void sleep_until_ns(int64_t t_ns) override;
};

}  // namespace hd::render
