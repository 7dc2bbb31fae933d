#pragma once
// When each simulated camera frame is exposed, delivered or lost: the dropped_frames,
// camera_delay and network_delay effects. Deterministic per (seed, camera, sequence).

#include <cstdint>
#include <optional>

#include "sim/scene/scene.h"
#include "sim/simulation.h"

namespace hd::sim {

class FrameTimingModel {
 public:
  FrameTimingModel(const SceneEffects& effects, double rate_hz, uint64_t camera_stream);

  /// For a camera that started at the epoch: exposure = sequence / rate_hz.
  SimFrameTiming at(uint64_t sequence) const;
  /// camera delay + network delay of frame `sequence`: each mean + jitter * N(0,1), cut at 0.
  int64_t delay_ns(uint64_t sequence) const;
  bool dropped(uint64_t sequence) const;
  bool has_delay() const { return camera_delay_ || network_delay_; }
  bool has_drops() const { return drops_.has_value(); }

 private:
  std::optional<DelayEffect> camera_delay_, network_delay_;
  std::optional<DroppedFramesEffect> drops_;
  int64_t period_ns_;
  uint64_t stream_;
};

}  // namespace hd::sim
