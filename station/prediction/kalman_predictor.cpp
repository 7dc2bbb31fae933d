#include "station/prediction/kalman_predictor.h"

#include "station/prediction/so3.h"

namespace hd::station {
namespace {
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat36 = Eigen::Matrix<double, 3, 6>;
}  // namespace

void KalmanPredictor::initialise(const HeadSample& s) {
  t_ns_ = s.t_ns;
  q_ = s.q_world_head;
  omega_ = s.has_omega ? s.omega_head_rad_s : Eigen::Vector3d::Zero();
  p_ = s.p_world_m;
  v_.setZero();
  P_rot_.setZero();
  const double var_theta = params_.orientation_noise_rad * params_.orientation_noise_rad;
  const double sd_omega =
      s.has_omega ? params_.gyro_noise_rad_s : params_.initial_angular_rate_rad_s;
  P_rot_.topLeftCorner<3, 3>() = var_theta * Eigen::Matrix3d::Identity();
  P_rot_.bottomRightCorner<3, 3>() = sd_omega * sd_omega * Eigen::Matrix3d::Identity();
  P_pos_ << params_.position_noise_m * params_.position_noise_m, 0.0, 0.0,
      params_.initial_velocity_m_s * params_.initial_velocity_m_s;
  initialised_ = true;
}

void KalmanPredictor::propagate(double dt) {
  q_ = (q_ * so3_exp(omega_ * dt)).normalized();
  Mat6 F = Mat6::Identity();
  F.topLeftCorner<3, 3>() = so3_exp(-omega_ * dt).toRotationMatrix();
  F.topRightCorner<3, 3>() = dt * Eigen::Matrix3d::Identity();
  const double qa = params_.angular_accel_psd * params_.angular_accel_psd;
  Mat6 Q = Mat6::Zero();
  Q.topLeftCorner<3, 3>() = qa * dt * dt * dt / 3.0 * Eigen::Matrix3d::Identity();
  Q.topRightCorner<3, 3>() = qa * dt * dt / 2.0 * Eigen::Matrix3d::Identity();
  Q.bottomLeftCorner<3, 3>() = Q.topRightCorner<3, 3>();
  Q.bottomRightCorner<3, 3>() = qa * dt * Eigen::Matrix3d::Identity();
  P_rot_ = F * P_rot_ * F.transpose() + Q;

  p_ += v_ * dt;
  Eigen::Matrix2d Fp;
  Fp << 1.0, dt, 0.0, 1.0;
  const double ql = params_.linear_accel_psd * params_.linear_accel_psd;
  Eigen::Matrix2d Qp;
  Qp << ql * dt * dt * dt / 3.0, ql * dt * dt / 2.0, ql * dt * dt / 2.0, ql * dt;
  P_pos_ = Fp * P_pos_ * Fp.transpose() + Qp;
}

void KalmanPredictor::observe(const HeadSample& s) {
  if (!initialised_) {
    initialise(s);
    return;
  }
  const double dt = static_cast<double>(s.t_ns - t_ns_) * 1e-9;
  if (dt > 0.0) propagate(dt);
  t_ns_ = s.t_ns;

  // Joseph-form updates keep P symmetric positive definite in floating point.
  auto update_rot = [this](const Eigen::Vector3d& r, const Mat36& H, double var) {
    const Eigen::Matrix3d S = H * P_rot_ * H.transpose() + var * Eigen::Matrix3d::Identity();
    const Mat63 K = P_rot_ * H.transpose() * S.inverse();
    const Eigen::Matrix<double, 6, 1> dx = K * r;
    q_ = (q_ * so3_exp(dx.head<3>())).normalized();
    omega_ += dx.tail<3>();
    const Mat6 IKH = Mat6::Identity() - K * H;
    P_rot_ = IKH * P_rot_ * IKH.transpose() + var * K * K.transpose();
  };
  Mat36 H_theta = Mat36::Zero();
  H_theta.leftCols<3>().setIdentity();
  update_rot(so3_log(q_.conjugate() * s.q_world_head), H_theta,
             params_.orientation_noise_rad * params_.orientation_noise_rad);
  if (s.has_omega) {
    Mat36 H_omega = Mat36::Zero();
    H_omega.rightCols<3>().setIdentity();
    update_rot(s.omega_head_rad_s - omega_, H_omega,
               params_.gyro_noise_rad_s * params_.gyro_noise_rad_s);
  }

  if (s.has_position) {
    const double var = params_.position_noise_m * params_.position_noise_m;
    const double S = P_pos_(0, 0) + var;
    const Eigen::Vector2d K(P_pos_(0, 0) / S, P_pos_(1, 0) / S);
    const Eigen::Vector3d r = s.p_world_m - p_;
    p_ += K(0) * r;
    v_ += K(1) * r;
    Eigen::Matrix2d IKH = Eigen::Matrix2d::Identity();
    IKH(0, 0) -= K(0);
    IKH(1, 0) -= K(1);
    P_pos_ = IKH * P_pos_ * IKH.transpose() + var * K * K.transpose();
  }
}

core::Pose KalmanPredictor::predict(int64_t t_ns) const {
  if (!initialised_) return core::Pose::identity();
  const double h = static_cast<double>(t_ns - t_ns_) * 1e-9;
  return core::Pose::from(q_ * so3_exp(omega_ * h), p_ + v_ * h);
}

}  // namespace hd::station
