#include "sim/stepped_head.h"

#include <cmath>

namespace hd::sim {

SteppedHead::SteppedHead(const Simulation& sim, int64_t epoch_ns)
    : sim_(sim),
      epoch_ns_(epoch_ns),
      period_ns_(static_cast<int64_t>(std::llround(1e9 / sim.scene().head.rate_hz))) {}

drivers::SourceState SteppedHead::state() const {
  return running_ ? drivers::SourceState::kStreaming : drivers::SourceState::kClosed;
}

uint64_t SteppedHead::advance_to(int64_t now_ns) {
  if (!running_) return 0;
  uint64_t published = 0;
  for (;;) {
    const int64_t t_ns = static_cast<int64_t>(next_sequence_) * period_ns_;
    if (epoch_ns_ + t_ns > now_ns) break;
    drivers::PoseSample& s = latest_.write_slot();
    s = sim_.head_sample(static_cast<double>(t_ns) * 1e-9, next_sequence_);
    s.host_timestamp_ns = epoch_ns_ + t_ns;
    s.device_timestamp_ns = t_ns;
    history_.push(s);
    latest_.publish();
    ++next_sequence_;
    ++published;
  }
  return published;
}

}  // namespace hd::sim
