#pragma once
// Disparity -> workspace points: the rectified Q, the left camera's rectifying rotation and its
// pose P_c, folded into one projective map.

#include <Eigen/Core>
#include <optional>

#include "recon/rectification.h"

namespace hd::recon {

/// X_world = T_world_left * R_rect_left^T * dehomogenise(Q * (x, y, d, 1)), x, y in rectified
/// left pixels (OpenCV centres), d in pixels. Metres.
class DisparityToWorld {
 public:
  explicit DisparityToWorld(const Rectification& rect);

  /// The workspace point of (x, y, d); nothing for an unknown (NaN), zero, negative or infinite
  /// disparity: d = 0 would be a point at infinity, d < 0 one behind the cameras.
  std::optional<Eigen::Vector3d> point(double x, double y, double d) const {
    if (!(d > 0.0) || !(d < kMaxDisparityPx)) return std::nullopt;
    const Eigen::Vector4d h = M_ * Eigen::Vector4d(x, y, d, 1.0);
    if (!(h.w() > 0.0)) return std::nullopt;
    return h.head<3>() / h.w();
  }

  /// The same point in the left camera's own frame (nothing as point()).
  std::optional<Eigen::Vector3d> left_point(double x, double y, double d) const;

 private:
  static constexpr double kMaxDisparityPx = 1e6;
  Eigen::Matrix4d M_;       ///< world <- (x, y, d, 1)
  Eigen::Matrix4d M_left_;  ///< left camera frame <- (x, y, d, 1)
};

}  // namespace hd::recon
