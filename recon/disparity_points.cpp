#include "recon/disparity_points.h"

namespace hd::recon {

DisparityToWorld::DisparityToWorld(const Rectification& rect) {
  Eigen::Matrix4d Q, R = Eigen::Matrix4d::Identity(), T = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) Q(i, j) = rect.Q()(i, j);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = rect.R_rect_left()(j, i);  // transpose: rect -> left
  const core::Pose& P = rect.rig().T_world_left;
  T.topLeftCorner<3, 3>() = P.R;
  T.topRightCorner<3, 1>() = P.t;
  M_left_ = R * Q;
  M_ = T * M_left_;
}

std::optional<Eigen::Vector3d> DisparityToWorld::left_point(double x, double y, double d) const {
  if (!(d > 0.0) || !(d < kMaxDisparityPx)) return std::nullopt;
  const Eigen::Vector4d h = M_left_ * Eigen::Vector4d(x, y, d, 1.0);
  if (!(h.w() > 0.0)) return std::nullopt;
  return Eigen::Vector3d(h.head<3>() / h.w());
}

}  // namespace hd::recon
