#pragma once
// The fixed-rate render loop: one slot per display period, a deadline per frame, self-paced.

#include <cstdint>

#include "render/loop/loop_clock.h"

namespace hd::render {

struct FrameLoopConfig {
  double rate_hz = 90.0;  ///< 60, 72, 90 for HMDs; any positive finite rate is accepted
  /// From the (estimated) vsync to photons: the display's scan-out + pixel response.
  int64_t scanout_latency_ns = 0;
  /// Sleep until each slot starts. Off only for benchmarks that want back-to-back frames.
  bool pace = true;
};

/// What one frame is drawn for. The expected display time is the next vsync estimate (the end
/// of this slot) plus the scan-out latency: the head pose is predicted to it.
struct FrameTiming {
  uint64_t frame = 0;
  int64_t start_ns = 0;     ///< slot start (the previous vsync estimate)
  int64_t deadline_ns = 0;  ///< start + period: present must have happened by then
  int64_t display_ns = 0;   ///< deadline + scan-out latency
  double dt_s = 0.0;        ///< since the previous frame's slot start (0 for the first)
};

/// The per-frame work; the loop calls it once per slot. Must not allocate, lock or throw.
class FrameWork {
 public:
  virtual ~FrameWork() = default;
  virtual void tick(const FrameTiming& timing) = 0;
};

/// Slots start at t0 + k * period. A frame that ends after its deadline is counted as missed;
/// slots that passed while it ran are skipped (counted) so the loop stays phase-locked to the
/// display instead of bunching frames to catch up. Under Xvfb swap does not throttle, so the
/// loop always paces itself with absolute sleeps.
class FrameLoop {
 public:
  FrameLoop(FrameLoopConfig config, LoopClock& clock);

  /// Runs one frame (sleeping until its slot when pacing). Returns its timing.
  FrameTiming tick(FrameWork& work);
  /// Runs `frames` frames.
  void run(uint64_t frames, FrameWork& work);

  /// Runs at the display rate / `divisor` from the next slot on (RateGovernor): slots stay on
  /// the display's vsync grid. std::invalid_argument below 1.
  void set_divisor(int divisor);
  int divisor() const { return divisor_; }
  /// The period in use: the display's times the divisor.
  int64_t period_ns() const { return period_ns_; }
  /// How long the newest frame's work took (from when it began, after any sleep, to its end).
  int64_t last_work_ns() const { return last_work_ns_; }
  uint64_t frames() const { return frames_; }
  uint64_t missed_deadlines() const { return missed_; }
  uint64_t skipped_slots() const { return skipped_; }
  /// Time from the slot deadline to the end of the newest frame's work (negative: slack).
  int64_t last_lateness_ns() const { return last_lateness_ns_; }

 private:
  FrameLoopConfig config_;
  LoopClock& clock_;
  int64_t display_period_ns_;
  int64_t period_ns_;
  int divisor_ = 1;
  int64_t last_work_ns_ = 0;
  bool started_ = false;
  int64_t next_start_ns_ = 0;
  int64_t prev_start_ns_ = 0;
  uint64_t frames_ = 0;
  uint64_t missed_ = 0;
  uint64_t skipped_ = 0;
  int64_t last_lateness_ns_ = 0;
};

}  // namespace hd::render
