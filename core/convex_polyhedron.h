#pragma once
// A bounded convex polyhedron: an axis-aligned box cut by a few half-spaces, held as its face
// polygons. W (the observation space) is one of these; its vertices are the faces' vertices.

#include <array>

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
};

}  // namespace hd::core
