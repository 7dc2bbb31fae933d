#include "station/prediction/simulated_head_motion.h"

#include <cmath>
#include <cstddef>
#include <numbers>

#include "station/prediction/so3.h"

namespace hd::station {
namespace {
struct Wave {
  double amplitude;
  double hz;
  double phase;
};
template <std::size_t N>
double sum(const Wave (&w)[N], double t_s) {
  double s = 0.0;
  for (const Wave& x : w)
    s += x.amplitude * std::sin(2.0 * std::numbers::pi * x.hz * t_s + x.phase);
  return s;
}
constexpr double kDeg = std::numbers::pi / 180.0;
// Seated head motion: slow large turns, faster small corrections (rates up to ~100 deg/s).
constexpr Wave kYaw[] = {{25 * kDeg, 0.25, 0.0}, {10 * kDeg, 0.7, 1.0}, {3 * kDeg, 1.9, 2.0}};
constexpr Wave kPitch[] = {{10 * kDeg, 0.35, 0.5}, {4 * kDeg, 1.1, 0.2}};
constexpr Wave kRoll[] = {{3 * kDeg, 0.5, 1.3}};
constexpr Wave kX[] = {{0.05, 0.3, 0.0}, {0.01, 1.3, 0.7}};
constexpr Wave kY[] = {{0.02, 0.45, 0.3}};
constexpr Wave kZ[] = {{0.04, 0.2, 1.1}};
// Held out (HeadMotionProfile::kHeldOut): none of the frequencies above, more high-frequency
// content. Over 60 s: yaw rate up to 127 deg/s and yaw acceleration up to 960 deg/s^2 (rms 415),
// pitch acceleration up to 500 deg/s^2; the tuning motion's are 119 deg/s, 670 deg/s^2 (rms 335)
// and 240 deg/s^2.
constexpr Wave kYaw2[] = {
    {20 * kDeg, 0.18, 0.4}, {12 * kDeg, 0.55, 2.1}, {4 * kDeg, 1.6, 0.9}, {1.5 * kDeg, 2.6, 1.7}};
constexpr Wave kPitch2[] = {{8 * kDeg, 0.42, 1.9}, {5 * kDeg, 0.9, 0.6}, {1.5 * kDeg, 2.2, 0.3}};
constexpr Wave kRoll2[] = {{4 * kDeg, 0.33, 0.8}, {1 * kDeg, 1.4, 2.5}};
constexpr Wave kX2[] = {{0.04, 0.22, 1.6}, {0.015, 0.95, 0.2}};
constexpr Wave kY2[] = {{0.015, 0.6, 2.2}, {0.005, 1.7, 0.4}};
constexpr Wave kZ2[] = {{0.03, 0.27, 0.5}, {0.01, 0.8, 1.9}};
}  // namespace

core::Pose SimulatedHeadMotion::pose(double t) const {
  const bool held_out = profile_ == HeadMotionProfile::kHeldOut;
  const double yaw = scale_ * (held_out ? sum(kYaw2, t) : sum(kYaw, t));
  const double pitch = scale_ * (held_out ? sum(kPitch2, t) : sum(kPitch, t));
  const double roll = scale_ * (held_out ? sum(kRoll2, t) : sum(kRoll, t));
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(Eigen::AngleAxisd(yaw, -Eigen::Vector3d::UnitY())) *
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
      Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d p =
      centre_m_ + scale_ * (held_out ? Eigen::Vector3d(sum(kX2, t), sum(kY2, t), sum(kZ2, t))
                                     : Eigen::Vector3d(sum(kX, t), sum(kY, t), sum(kZ, t)));
  return core::Pose::from(q, p);
}

Eigen::Vector3d SimulatedHeadMotion::angular_velocity_head(double t_s) const {
  constexpr double h = 0.5e-6;
  const Eigen::Quaterniond a(pose(t_s - h).R);
  const Eigen::Quaterniond b(pose(t_s + h).R);
  return so3_log(a.conjugate() * b) / (2.0 * h);
}

drivers::PoseSample SimulatedTracker::sample(int64_t t_ns) {
  const double t_s = static_cast<double>(t_ns) * 1e-9;
  const core::Pose truth = motion_.pose(t_s);
  auto noise3 = [this](double sd) {
    // Fixed order (arguments are unsequenced, GCC and clang differ): z, y, x as GCC drew them.
    const double z = sd * unit_(rng_), y = sd * unit_(rng_), x = sd * unit_(rng_);
    return Eigen::Vector3d(x, y, z);
  };
  drivers::PoseSample s;
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(truth.R) * so3_exp(noise3(noise_.orientation_rad));
  s.T_tracker_head = core::Pose::from(q, truth.t + noise3(noise_.position_m));
  s.has_position = true;
  s.has_angular_velocity = with_gyro_;
  if (with_gyro_)
    s.angular_velocity_rad_s = motion_.angular_velocity_head(t_s) + noise3(noise_.gyro_rad_s);
  s.sequence = sequence_++;
  s.host_timestamp_ns = t_ns;
  s.device_timestamp_ns = t_ns;
  s.device_time_trusted = true;
  return s;
}

}  // namespace hd::station
