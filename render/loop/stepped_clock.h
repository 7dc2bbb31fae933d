#pragma once
// A clock that moves only when told: the scene's clock for a run driven frame by frame
// (`hybrid-station score`: frame k at k / rate whatever the machine's speed) and the fake clock of
// the tests. It is the other side of the LoopClock seam from MonotonicLoopClock.
//
// sleep_until_ns(t) returns at once with the clock at t (if t is ahead): in a stepped run nothing
// else happens while a stage "waits", so waiting is jumping. Reads and moves are atomic, so a
// stage running on its own thread (the model updater) may share it.

#include <atomic>
#include <cstdint>

#include "render/loop/loop_clock.h"

namespace hd::render {

class SteppedLoopClock final : public LoopClock {
 public:
  explicit SteppedLoopClock(int64_t start_ns = 0) : now_(start_ns) {}

  int64_t now_ns() override { return now_.load(std::memory_order_acquire); }

  /// Jumps to t_ns if it lies ahead; time never goes back.
  void sleep_until_ns(int64_t t_ns) override {
    int64_t cur = now_.load(std::memory_order_acquire);
    while (t_ns > cur && !now_.compare_exchange_weak(cur, t_ns, std::memory_order_acq_rel)) {
    }
  }

  /// Sets the time, backwards too (a test replaying a moment; a run only moves it forward).
  void set_ns(int64_t t_ns) { now_.store(t_ns, std::memory_order_release); }

 private:
  std::atomic<int64_t> now_;
};

}  // namespace hd::render
