#pragma once
// A bounded convex polyhedron: an axis-aligned box cut by a few half-spaces, held as its face
// polygons. W (the observation space) is one of these; its vertices are the faces' vertices.

#include <Eigen/Geometry>
#include <array>
#include <cmath>

#include "core/convex_polygon.h"
#include "core/half_space.h"
#include "core/workspace_box.h"

namespace hd::core {

struct ConvexPolyhedron {
  static constexpr int kMaxCuts = 8;
  static constexpr int kMaxFaces = 6 + kMaxCuts;
  /// A face starts as a quad (box face or square on a cut plane), is clipped by the 6 box planes
  /// and the other cuts; each clip adds at most one vertex.
  using Face = ConvexPolygon<3, 4 + 6 + kMaxCuts>;

  std::array<Face, kMaxFaces> faces;
  int face_count = 0;      ///< faces with at least one vertex
  int box_face_count = 0;  ///< faces[0..box_face_count) lie on box planes, the rest on cuts
  WorkspaceBox box;
  double tol_m = 0.0;

  bool empty() const { return face_count == 0; }

  /// Calls f(vertex) for every face vertex; a vertex shared by k faces is visited k times, which is
  /// harmless for maxima and avoids a dedup pass on the per-frame path.
  template <class F>
  void for_each_vertex(F&& f) const {
    for (int i = 0; i < face_count; ++i)
      for (int k = 0; k < faces[i].size(); ++k) f(faces[i][k]);
  }

  /// Calls f(vertex) for every vertex at most about 3 times instead of up to 6: a vertex of a
  /// cut face that lies on a box plane is also a vertex of that box face, so it is skipped there.
  template <class F>
  void for_each_vertex_once_per_box_face(F&& f) const {
    for (int i = 0; i < face_count; ++i)
      for (int k = 0; k < faces[i].size(); ++k) {
        const Eigen::Vector3d& v = faces[i][k];
        if (i >= box_face_count && on_box_plane(v)) continue;
        f(v);
      }
  }

  bool on_box_plane(const Eigen::Vector3d& v) const {
    return ((v - box.min_m).cwiseAbs().array() <= tol_m).any() ||
           ((v - box.max_m).cwiseAbs().array() <= tol_m).any();
  }

  /// box ∩ cuts[0..n_cuts). Points within tol_m of a plane count as inside it (flat boxes, grazing
  /// planes). Returns an empty polyhedron for n_cuts > kMaxCuts or an invalid box. Cut normals need
  /// not be unit length. No allocation.
  static ConvexPolyhedron box_cut_by(const WorkspaceBox& box, const HalfSpace3* cuts, int n_cuts,
                                     double tol_m);

  /// The cuts, normalised, that really cut the box into `out`; returns their number, or -1 when
  /// box ∩ cuts is empty (a cut holds no corner), the box is invalid, a cut is not finite, or
  /// n_cuts > kMaxCuts. A cut holding all 8 corners changes nothing and is dropped.
  static int cutting_planes(const WorkspaceBox& box, const HalfSpace3* cuts, int n_cuts,
                            double tol_m, std::array<HalfSpace3, kMaxCuts>& out);

  /// Calls f(vertex) for every vertex of box ∩ cuts (same tolerance rules as box_cut_by) without
  /// building the polyhedron: the per-frame E_max only needs the vertices. A vertex is either on a
  /// box face (the box faces clipped by the cuts, quads and cheap) or strictly inside the box,
  /// where it is the meeting point of three cut planes; the latter are found by solving each triple
  /// instead of clipping a polygon on every cut plane by 6 box planes and the other cuts, which was
  /// most of the per-frame time. Vertices may still be visited more than once (harmless for
  /// maxima). Returns false when the polyhedron is empty.
  template <class F>
  static bool for_each_vertex_of_box_cut(const WorkspaceBox& box, const HalfSpace3* cuts,
                                         int n_cuts, double tol_m, F&& f);
};

template <class F>
bool ConvexPolyhedron::for_each_vertex_of_box_cut(const WorkspaceBox& box, const HalfSpace3* cuts,
                                                  int n_cuts, double tol_m, F&& f) {
  std::array<HalfSpace3, kMaxCuts> unit;
  const int n = cutting_planes(box, cuts, n_cuts, tol_m, unit);
  if (n < 0) return false;
  const Eigen::Vector3d& lo = box.min_m;
  const Eigen::Vector3d& hi = box.max_m;
  bool any = false;
  // Box faces: each quad already satisfies the box planes, so only the cuts clip it; a quad cut
  // by n planes has at most 4 + n vertices.
  for (int a = 0; a < 3; ++a) {
    const int b1 = (a + 1) % 3;
    const int b2 = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      ConvexPolygon<3, 4 + kMaxCuts> q;
      Eigen::Vector3d p;
      p[a] = side == 0 ? lo[a] : hi[a];
      const double u[4] = {lo[b1], hi[b1], hi[b1], lo[b1]};
      const double v[4] = {lo[b2], lo[b2], hi[b2], hi[b2]};
      for (int k = 0; k < 4; ++k) {
        p[b1] = u[k];
        p[b2] = v[k];
        q.push_back(p);
      }
      for (int i = 0; i < n && !q.empty(); ++i) q.clip(unit[i], tol_m);
      any = any || !q.empty();
      for (int k = 0; k < q.size(); ++k) {
        // A vertex on a box plane of a lower axis is a vertex of that axis' face polygon too and
        // was visited there: skipping it visits box corners once instead of three times.
        bool seen = false;
        for (int b = 0; b < a && !seen; ++b)
          seen = std::abs(q[k][b] - lo[b]) <= tol_m || std::abs(q[k][b] - hi[b]) <= tol_m;
        if (!seen) f(q[k]);
      }
    }
  }
  // Interior vertices: three cut planes meeting inside the box and inside every other cut.
  // Triples with (nearly) dependent normals meet in a line or not at all: no vertex of their own.
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Eigen::Vector3d nij = unit[i].n.cross(unit[j].n);
      for (int k = j + 1; k < n; ++k) {
        const double det = unit[k].n.dot(nij);
        if (!(std::abs(det) > 1e-9)) continue;
        const Eigen::Vector3d njk = unit[j].n.cross(unit[k].n);
        const Eigen::Vector3d nki = unit[k].n.cross(unit[i].n);
        const Eigen::Vector3d X = -(unit[i].c * njk + unit[j].c * nki + unit[k].c * nij) / det;
        if (!((X.array() >= lo.array() - tol_m).all() && (X.array() <= hi.array() + tol_m).all()))
          continue;
        bool inside = true;
        for (int m = 0; m < n && inside; ++m)
          if (m != i && m != j && m != k) inside = unit[m].signed_distance(X) >= -tol_m;
        if (inside) {
          f(X);
          any = true;
        }
      }
    }
  return any;
}

}  // namespace hd::core
