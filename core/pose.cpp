#include "core/pose.h"

#include <cmath>

namespace hd::core {

bool Pose::valid(double tol) const {
  if (!R.allFinite() || !t.allFinite()) return false;
  const double ortho_err = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  return ortho_err <= tol && std::abs(R.determinant() - 1.0) <= tol;
}

}  // namespace hd::core
