#pragma once
// Kalman filter predictor: an error-state (multiplicative) EKF for orientation + angular velocity
// and a linear constant-velocity filter for position.

#include <Eigen/Core>

#include "station/prediction/pose_predictor.h"

namespace hd::station {

/// Noise model. Process noise is white acceleration (the derivative of the velocity states is
/// white noise of the given spectral density); measurement noise is white per sample.
struct KalmanParams {
  double orientation_noise_rad = 0.002;   ///< tracker orientation noise (1 sigma, per axis)
  double gyro_noise_rad_s = 0.02;         ///< tracker gyro noise (1 sigma, per axis)
  double position_noise_m = 0.0005;       ///< tracker position noise (1 sigma, per axis)
  double angular_accel_psd = 2.0;         ///< rad/s^2 per sqrt(Hz)
  double linear_accel_psd = 0.2;          ///< m/s^2 per sqrt(Hz)
  double initial_angular_rate_rad_s = 2;  ///< prior sigma of omega before any data
  double initial_velocity_m_s = 1.0;      ///< prior sigma of v before any data
};

/// Formulation (documented in docs/station.md):
///  orientation state: nominal q (head->world) and omega (head frame); the filter's 6-vector
///  error state is [dtheta, domega] with q_true = q * exp(dtheta) (right, body-frame error).
///  Propagation over dt: q <- q*exp(omega dt); F = [[exp(-[omega]x dt), I dt], [0, I]],
///  Q = psd^2 [[dt^3/3 I, dt^2/2 I], [dt^2/2 I, dt I]].
///  Orientation measurement: r = log(q^-1 q_meas), H = [I 0]; gyro: r = w_meas - omega, H = [0 I].
///  After each update the error is folded into q and reset to zero.
///  Position: per axis [p, v] with F = [[1, dt], [0, 1]] and the same Q form (one 2x2 covariance
///  shared by the three axes, as their noise is the same).
/// predict(t) extrapolates the filtered state from the newest sample's time to t.
class KalmanPredictor final : public PosePredictor {
 public:
  explicit KalmanPredictor(KalmanParams params = {}) : params_(params) {}
  std::string_view name() const override { return "Kalman"; }
  void reset() override { initialised_ = false; }
  void observe(const HeadSample& s) override;
  bool ready() const override { return initialised_; }
  core::Pose predict(int64_t t_ns) const override;

  const Eigen::Quaterniond& orientation() const { return q_; }
  const Eigen::Vector3d& angular_velocity_head_rad_s() const { return omega_; }
  const Eigen::Vector3d& position_m() const { return p_; }
  const Eigen::Vector3d& velocity_m_s() const { return v_; }
  /// Posterior variances (the filter's own view of its accuracy).
  const Eigen::Matrix<double, 6, 6>& orientation_covariance() const { return P_rot_; }
  const Eigen::Matrix2d& position_covariance_per_axis() const { return P_pos_; }

 private:
  void initialise(const HeadSample& s);
  void propagate(double dt_s);

  KalmanParams params_;
  bool initialised_ = false;
  int64_t t_ns_ = 0;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d omega_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_ = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 6, 6> P_rot_ = Eigen::Matrix<double, 6, 6>::Identity();
  Eigen::Matrix2d P_pos_ = Eigen::Matrix2d::Identity();
};

}  // namespace hd::station
