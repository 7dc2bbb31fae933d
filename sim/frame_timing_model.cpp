#include "sim/frame_timing_model.h"

#include <algorithm>
#include <cmath>

#include "sim/sim_random.h"

namespace hd::sim {

namespace {

// Distinct streams so the camera delay, the network delay and the drops of one camera are
// independent even with equal seeds.
constexpr uint64_t kCameraDelayStream = 0x100;
constexpr uint64_t kNetworkDelayStream = 0x200;
constexpr uint64_t kDropStream = 0x300;

int64_t draw_delay_ns(const DelayEffect& d, uint64_t stream, uint64_t sequence) {
  const double ms = d.mean_ms + d.jitter_ms * random_normal(d.seed, stream, sequence);
  return static_cast<int64_t>(std::llround(std::max(ms, 0.0) * 1e6));
}

}  // namespace

FrameTimingModel::FrameTimingModel(const SceneEffects& effects, double rate_hz,
                                   uint64_t camera_stream)
    : camera_delay_(effects.camera_delay),
      network_delay_(effects.network_delay),
      drops_(effects.dropped_frames),
      period_ns_(static_cast<int64_t>(std::llround(1e9 / rate_hz))),
      stream_(camera_stream << 16) {}

int64_t FrameTimingModel::delay_ns(uint64_t sequence) const {
  int64_t total = 0;
  if (camera_delay_) total += draw_delay_ns(*camera_delay_, stream_ + kCameraDelayStream, sequence);
  if (network_delay_) {
    total += draw_delay_ns(*network_delay_, stream_ + kNetworkDelayStream, sequence);
  }
  return total;
}

bool FrameTimingModel::dropped(uint64_t sequence) const {
  return drops_ &&
         random_uniform(drops_->seed, stream_ + kDropStream, sequence) < drops_->probability;
}

SimFrameTiming FrameTimingModel::at(uint64_t sequence) const {
  SimFrameTiming t;
  t.exposure_offset_ns = static_cast<int64_t>(sequence) * period_ns_;
  t.delivery_delay_ns = delay_ns(sequence);
  t.dropped = dropped(sequence);
  return t;
}

}  // namespace hd::sim
