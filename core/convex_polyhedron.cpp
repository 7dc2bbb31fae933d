#include "core/convex_polyhedron.h"

#include <Eigen/Geometry>
#include <cmath>

namespace hd::core {

namespace {

std::array<HalfSpace3, 6> box_planes(const WorkspaceBox& b) {
  std::array<HalfSpace3, 6> h;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[a] = 1.0;
    h[2 * a] = {n, -b.min_m[a]};      // x_a >= min
    h[2 * a + 1] = {-n, b.max_m[a]};  // x_a <= max
  }
  return h;
}

}  // namespace

int ConvexPolyhedron::cutting_planes(const WorkspaceBox& box, const HalfSpace3* cuts, int n_cuts,
                                     double tol_m, std::array<HalfSpace3, kMaxCuts>& out) {
  if (!box.valid() || n_cuts < 0 || n_cuts > kMaxCuts) return -1;
  const Eigen::Vector3d& lo = box.min_m;
  const Eigen::Vector3d& hi = box.max_m;
  int n_out = 0;
  for (int i = 0; i < n_cuts; ++i) {
    const HalfSpace3 h = cuts[i].normalized();
    if (!h.n.allFinite() || !std::isfinite(h.c)) return -1;
    int inside = 0;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d corner(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(),
                                   k & 4 ? hi.z() : lo.z());
      inside += h.signed_distance(corner) >= -tol_m;
    }
    if (inside == 0) return -1;
    if (inside < 8) out[n_out++] = h;
  }
  return n_out;
}

ConvexPolyhedron ConvexPolyhedron::box_cut_by(const WorkspaceBox& box, const HalfSpace3* cuts,
                                              int n_cuts, double tol_m) {
  ConvexPolyhedron out;
  out.box = box;
  out.tol_m = tol_m;
  std::array<HalfSpace3, kMaxCuts> unit;
  n_cuts = cutting_planes(box, cuts, n_cuts, tol_m, unit);
  if (n_cuts < 0) return out;
  const Eigen::Vector3d& lo = box.min_m;
  const Eigen::Vector3d& hi = box.max_m;
  const auto bp = box_planes(box);

  // Box faces: the face quad already satisfies the box planes, so only the cuts clip it.
  for (int a = 0; a < 3; ++a) {
    const int b1 = (a + 1) % 3;
    const int b2 = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      Face f;
      Eigen::Vector3d p;
      p[a] = side == 0 ? lo[a] : hi[a];
      const double u[4] = {lo[b1], hi[b1], hi[b1], lo[b1]};
      const double v[4] = {lo[b2], lo[b2], hi[b2], hi[b2]};
      for (int k = 0; k < 4; ++k) {
        p[b1] = u[k];
        p[b2] = v[k];
        f.push_back(p);
      }
      for (int i = 0; i < n_cuts && !f.empty(); ++i) f.clip(unit[i], tol_m);
      if (!f.empty()) out.faces[out.face_count++] = f;
    }
  }

  out.box_face_count = out.face_count;

  // Cut faces: a square on the cut plane large enough to contain plane ∩ box (every point of the
  // box is within half the diagonal of its centre, and so is its projection on the plane).
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double half = 0.5 * (hi - lo).norm() + tol_m + 1e-9;
  for (int i = 0; i < n_cuts; ++i) {
    const Eigen::Vector3d& n = unit[i].n;
    int least = 0;
    n.cwiseAbs().minCoeff(&least);
    const Eigen::Vector3d e1 = n.cross(Eigen::Vector3d::Unit(least)).normalized();
    const Eigen::Vector3d e2 = n.cross(e1);
    const Eigen::Vector3d c0 = centre - unit[i].signed_distance(centre) * n;
    Face f;
    f.push_back(c0 + half * (e1 + e2));
    f.push_back(c0 + half * (-e1 + e2));
    f.push_back(c0 + half * (-e1 - e2));
    f.push_back(c0 + half * (e1 - e2));
    for (int k = 0; k < 6 && !f.empty(); ++k) f.clip(bp[k], tol_m);
    for (int j = 0; j < n_cuts && !f.empty(); ++j)
      if (j != i) f.clip(unit[j], tol_m);
    if (!f.empty()) out.faces[out.face_count++] = f;
  }
  return out;
}

}  // namespace hd::core
