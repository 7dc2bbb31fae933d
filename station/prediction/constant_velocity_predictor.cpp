#include "station/prediction/constant_velocity_predictor.h"

#include "station/prediction/so3.h"

namespace hd::station {

void ConstantVelocityPredictor::observe(const HeadSample& s) {
  ring_[next_] = s;
  next_ = (next_ + 1) % kWindow;
  if (count_ < kWindow) ++count_;

  const HeadSample& now = back(0);
  // The newest sample at least one window older (or the oldest one kept).
  std::size_t age = 1;
  while (age + 1 < count_ && now.t_ns - back(age).t_ns < params_.velocity_window_ns) ++age;
  if (count_ >= 2) {
    const HeadSample& then = back(age);
    const double dt_s = static_cast<double>(now.t_ns - then.t_ns) * 1e-9;
    // Body-frame rate: q_now = q_then * exp(omega * dt).
    omega_head_rad_s_ = so3_log(then.q_world_head.conjugate() * now.q_world_head) / dt_s;
    if (now.has_position && then.has_position)
      velocity_m_s_ = (now.p_world_m - then.p_world_m) / dt_s;
    else
      velocity_m_s_.setZero();
  }
  if (params_.use_device_angular_velocity && now.has_omega)
    omega_head_rad_s_ = now.omega_head_rad_s;
}

core::Pose ConstantVelocityPredictor::predict(int64_t t_ns) const {
  if (count_ == 0) return core::Pose::identity();
  const HeadSample& now = back(0);
  const double h_s = static_cast<double>(t_ns - now.t_ns) * 1e-9;
  const Eigen::Quaterniond q = now.q_world_head * so3_exp(omega_head_rad_s_ * h_s);
  return core::Pose::from(q, now.p_world_m + velocity_m_s_ * h_s);
}

}  // namespace hd::station
