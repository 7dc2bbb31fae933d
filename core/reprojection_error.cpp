#include "core/reprojection_error.h"

#include "core/camera_pair.h"

namespace hd::core {

std::optional<double> reprojection_error(const ViewSetup& s, const Eigen::Vector3d& X_world) {
  if (!s.valid() || !X_world.allFinite()) return std::nullopt;
  const CameraPair pair(s);
  const Eigen::Vector3d X_r = pair.real_from_world(X_world);
  if (!(X_r.z() > s.near_m)) return std::nullopt;
  if (!(pair.virt_from_real(X_r).z() > s.near_m)) return std::nullopt;
  return pair.error_px(X_r);
}

}  // namespace hd::core
