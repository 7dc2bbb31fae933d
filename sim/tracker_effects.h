#pragma once
// The tracker_noise and tracker_drift effects on head pose samples.

#include <optional>

#include "drivers/pose_source.h"
#include "sim/scene/scene.h"

namespace hd::sim {

/// Noise: the position gets N(0, sigma_m) per axis, the orientation a rotation vector with
/// N(0, sigma_deg) per axis (head frame), drawn per sample from (seed, sample sequence).
/// Drift: position += direction * rate_m_s * t, orientation turned by rate_deg_s * t about `axis`
/// (tracker frame) -- a slowly walking reference frame. Angular velocity is left as measured.
class TrackerEffects {
 public:
  explicit TrackerEffects(const SceneEffects& effects);
  bool empty() const { return !noise_ && !drift_; }
  void apply(drivers::PoseSample& sample, double t_s) const;

 private:
  std::optional<TrackerNoiseEffect> noise_;
  std::optional<TrackerDriftEffect> drift_;
};

}  // namespace hd::sim
