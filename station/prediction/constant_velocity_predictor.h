#pragma once
// Constant-velocity extrapolation: orientation by angular velocity integrated on SO(3), position
// by a finite-difference velocity.

#include <array>
#include <cstddef>

#include "station/prediction/pose_predictor.h"

namespace hd::station {

struct ConstantVelocityParams {
  /// Velocities are differenced between the newest sample and the newest one at least this much
  /// older. Differencing adjacent 1 kHz samples would amplify sensor noise ~1000x; a short window
  /// trades a little lag for much less noise. Constant motion is predicted exactly either way.
  int64_t velocity_window_ns = 10'000'000;
  /// Use the tracker's gyro (head frame) when it reports one instead of differencing.
  bool use_device_angular_velocity = true;
};

/// pose(t) = { q_n * exp(omega * (t - t_n)),  p_n + v * (t - t_n) }, omega in the head frame.
class ConstantVelocityPredictor final : public PosePredictor {
 public:
  explicit ConstantVelocityPredictor(ConstantVelocityParams params = {}) : params_(params) {}
  std::string_view name() const override { return "constant velocity"; }
  void reset() override { count_ = 0; }
  void observe(const HeadSample& s) override;
  bool ready() const override { return count_ > 0; }
  core::Pose predict(int64_t t_ns) const override;

  /// The current velocity estimates (zero with fewer than two samples).
  const Eigen::Vector3d& angular_velocity_head_rad_s() const { return omega_head_rad_s_; }
  const Eigen::Vector3d& velocity_m_s() const { return velocity_m_s_; }

 private:
  static constexpr std::size_t kWindow = 128;
  const HeadSample& back(std::size_t age) const {
    return ring_[(next_ + kWindow - 1 - age) % kWindow];
  }

  ConstantVelocityParams params_;
  std::array<HeadSample, kWindow> ring_{};
  std::size_t next_ = 0;
  std::size_t count_ = 0;
  Eigen::Vector3d omega_head_rad_s_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s_ = Eigen::Vector3d::Zero();
};

}  // namespace hd::station
