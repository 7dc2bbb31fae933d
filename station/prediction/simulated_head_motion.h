#pragma once
// Head motion for prediction tests and benchmarks: a sum of sinusoids with the amplitudes and
// frequencies of seated head motion, plus a noisy tracker sampling it.

#include <cstdint>
#include <random>

#include "core/pose.h"
#include "drivers/pose_source.h"

namespace hd::station {

/// Which sums of sinusoids drive the motion. kTuning is the one the Kalman filter's default
/// process noise was chosen on (hybrid-bench-prediction); kHeldOut has other frequencies, phases
/// and amplitudes (a slower large turn, more and faster corrections: yaw +-37 deg, pitch +-15,
/// roll +-5, position +-5.5 cm, 0.18-2.6 Hz), so a predictor can be scored on motion it was not
/// tuned on.
enum class HeadMotionProfile { kTuning, kHeldOut };

/// The true motion. Orientation = yaw (about world -y, i.e. up) * pitch (x) * roll (z) of a camera
/// looking along +z; each angle and each position coordinate is a sum of sinusoids. Amplitudes are
/// scaled by `scale` (1 = typical: yaw +-38 deg, peak rates ~100 deg/s, position +-6 cm).
class SimulatedHeadMotion {
 public:
  explicit SimulatedHeadMotion(double scale = 1.0, Eigen::Vector3d centre_m = {0.0, 0.0, 0.0},
                               HeadMotionProfile profile = HeadMotionProfile::kTuning)
      : scale_(scale), centre_m_(centre_m), profile_(profile) {}
  core::Pose pose(double t_s) const;
  /// Body-frame (head) angular velocity, by a central difference 1 us wide (error ~1e-9 rad/s).
  Eigen::Vector3d angular_velocity_head(double t_s) const;

 private:
  double scale_;
  Eigen::Vector3d centre_m_;
  HeadMotionProfile profile_;
};

/// Tracker noise (1 sigma per axis); zero everywhere gives exact samples.
struct TrackerNoise {
  double orientation_rad = 0.0017;  // 0.1 deg
  double gyro_rad_s = 0.01;
  double position_m = 0.0003;
};

/// Samples a SimulatedHeadMotion like a tracker would: fixed rate, Gaussian noise, fixed seed.
class SimulatedTracker {
 public:
  SimulatedTracker(const SimulatedHeadMotion& motion, TrackerNoise noise, bool with_gyro,
                   uint32_t seed = 7)
      : motion_(motion), noise_(noise), with_gyro_(with_gyro), rng_(seed) {}
  drivers::PoseSample sample(int64_t t_ns);

 private:
  const SimulatedHeadMotion& motion_;
  TrackerNoise noise_;
  bool with_gyro_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> unit_{0.0, 1.0};
  uint64_t sequence_ = 0;
};

}  // namespace hd::station
