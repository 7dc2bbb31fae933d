#include "core/observation_space.h"

#include <algorithm>

namespace hd::core {

namespace {

HalfSpace3 to_world(const HalfSpace3& h_cam, const Pose& T_world_cam) {
  // n_cam . X_cam + c = n_cam . R^T (X - t) + c
  const Eigen::Vector3d n_w = T_world_cam.R * h_cam.n;
  return {n_w, h_cam.c - n_w.dot(T_world_cam.t)};
}

}  // namespace

std::array<HalfSpace3, 5> virtual_frustum_world(const ViewSetup& s) {
  const Pinhole& k = s.virt;
  const double w = k.width;
  const double h = k.height;
  // u >= 0  <=>  fx x + cx z >= 0 for z > 0; the others likewise.
  const std::array<HalfSpace3, 5> cam = {
      HalfSpace3{{k.fx, 0.0, k.cx}, 0.0},     HalfSpace3{{-k.fx, 0.0, w - k.cx}, 0.0},
      HalfSpace3{{0.0, k.fy, k.cy}, 0.0},     HalfSpace3{{0.0, -k.fy, h - k.cy}, 0.0},
      HalfSpace3{{0.0, 0.0, 1.0}, -s.near_m},
  };
  std::array<HalfSpace3, 5> out;
  for (int i = 0; i < 5; ++i) out[i] = to_world(cam[i].normalized(), s.T_world_virt);
  return out;
}

double geometry_tolerance_m(const ViewSetup& s) {
  const double scale = std::max(
      {s.workspace.min_m.cwiseAbs().maxCoeff(), s.workspace.max_m.cwiseAbs().maxCoeff(),
       s.T_world_real.t.cwiseAbs().maxCoeff(), s.T_world_virt.t.cwiseAbs().maxCoeff(), s.d_m, 1.0});
  return 1e-12 * scale;
}

std::array<HalfSpace3, 6> observation_space_cuts(const ViewSetup& s) {
  std::array<HalfSpace3, 6> cuts;
  const auto frustum = virtual_frustum_world(s);
  std::copy(frustum.begin(), frustum.end(), cuts.begin());
  cuts[5] = to_world(HalfSpace3{{0.0, 0.0, 1.0}, -s.near_m}, s.T_world_real);
  return cuts;
}

ConvexPolyhedron observation_space(const ViewSetup& s) {
  if (!s.valid()) return {};
  const auto cuts = observation_space_cuts(s);
  return ConvexPolyhedron::box_cut_by(s.workspace, cuts.data(), 6, geometry_tolerance_m(s));
}

}  // namespace hd::core
