#include "sim/tracker_effects.h"

#include <Eigen/Geometry>
#include <cmath>

#include "sim/sim_random.h"

namespace hd::sim {

namespace {
constexpr double kDeg = M_PI / 180.0;
constexpr uint64_t kTrackerStream = 0x7000;
}  // namespace

TrackerEffects::TrackerEffects(const SceneEffects& effects)
    : noise_(effects.tracker_noise), drift_(effects.tracker_drift) {}

void TrackerEffects::apply(drivers::PoseSample& s, double t_s) const {
  core::Pose& p = s.T_tracker_head;
  if (drift_) {
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(drift_->orientation_deg_s * kDeg * t_s, drift_->axis).toRotationMatrix();
    p.R = turn * p.R;
    p.t += drift_->direction * (drift_->position_m_s * t_s);
  }
  if (noise_) {
    const uint64_t base = 6 * s.sequence;
    Eigen::Vector3d dp, dr;
    for (int i = 0; i < 3; ++i) {
      dp[i] = noise_->position_sigma_m * random_normal(noise_->seed, kTrackerStream, base + i);
      dr[i] = noise_->orientation_sigma_deg * kDeg *
              random_normal(noise_->seed, kTrackerStream, base + 3 + i);
    }
    p.t += dp;
    if (dr.norm() > 0) p.R = p.R * Eigen::AngleAxisd(dr.norm(), dr.normalized()).toRotationMatrix();
  }
}

}  // namespace hd::sim
