// Convex polygon clipping and the box-cut polyhedron, checked against closed forms and against an
// independent vertex enumeration (every triple of planes, solved and tested against all planes).

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/Dense>
#include <vector>

#include "core/convex_polygon.h"
#include "core/convex_polyhedron.h"

using hd::core::ConvexPolygon;
using hd::core::ConvexPolyhedron;
using hd::core::HalfSpace2;
using hd::core::HalfSpace3;
using hd::core::WorkspaceBox;

namespace {

ConvexPolygon<2, 8> unit_square() {
  ConvexPolygon<2, 8> p;
  p.push_back({0, 0});
  p.push_back({1, 0});
  p.push_back({1, 1});
  p.push_back({0, 1});
  return p;
}

std::vector<Eigen::Vector3d> distinct(const ConvexPolyhedron& P, double tol) {
  std::vector<Eigen::Vector3d> out;
  P.for_each_vertex([&](const Eigen::Vector3d& v) {
    for (const auto& o : out)
      if ((o - v).norm() <= tol) return;
    out.push_back(v);
  });
  return out;
}

std::vector<Eigen::Vector3d> enumerate_vertices(const WorkspaceBox& b,
                                                const std::vector<HalfSpace3>& cuts, double tol) {
  std::vector<HalfSpace3> all = cuts;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d n = Eigen::Vector3d::Unit(a);
    all.push_back({n, -b.min_m[a]});
    all.push_back({-n, b.max_m[a]});
  }
  std::vector<Eigen::Vector3d> out;
  const int n = static_cast<int>(all.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        Eigen::Matrix3d A;
        A.row(0) = all[i].n.normalized();
        A.row(1) = all[j].n.normalized();
        A.row(2) = all[k].n.normalized();
        if (std::abs(A.determinant()) < 1e-6) continue;
        const Eigen::Vector3d rhs(-all[i].c / all[i].n.norm(), -all[j].c / all[j].n.norm(),
                                  -all[k].c / all[k].n.norm());
        const Eigen::Vector3d x = A.partialPivLu().solve(rhs);
        bool inside = true;
        for (const auto& h : all) inside = inside && h.normalized().signed_distance(x) >= -tol;
        if (!inside) continue;
        bool dup = false;
        for (const auto& o : out) dup = dup || (o - x).norm() <= 1e-7;
        if (!dup) out.push_back(x);
      }
  return out;
}

}  // namespace

TEST(ConvexPolygon, DiagonalCutHalvesTheSquare) {
  auto p = unit_square();
  p.clip(HalfSpace2{{-1, -1}, 1});  // x + y <= 1 (through two corners: duplicates allowed)
  EXPECT_LE(p.size(), 5);
  EXPECT_NEAR(std::abs(p.signed_area()), 0.5, 1e-15);
}

TEST(ConvexPolygon, CutAwayEntirelyAndKeptEntirely) {
  auto p = unit_square();
  p.clip(HalfSpace2{{1, 0}, -2});  // x >= 2
  EXPECT_TRUE(p.empty());
  auto q = unit_square();
  q.clip(HalfSpace2{{1, 0}, 5});  // x >= -5
  EXPECT_EQ(q.size(), 4);
  EXPECT_NEAR(std::abs(q.signed_area()), 1.0, 1e-15);
}

TEST(ConvexPolygon, CornerCutAddsOneVertex) {
  auto p = unit_square();
  p.clip(HalfSpace2{{-1, -1}, 1.5});  // x + y <= 1.5 cuts the corner (1,1)
  EXPECT_EQ(p.size(), 5);
  EXPECT_NEAR(std::abs(p.signed_area()), 1.0 - 0.125, 1e-15);
}

TEST(ConvexPolygon, FullCapacityReportsOverflow) {
  ConvexPolygon<2, 4> p;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(p.push_back({i, i * i}));
  EXPECT_FALSE(p.push_back({9, 9}));
  EXPECT_TRUE(p.overflowed());
}

TEST(ConvexPolyhedron, UncutBoxHasItsEightCorners) {
  const WorkspaceBox b{{0, 0, 0}, {1, 2, 3}};
  const auto P = ConvexPolyhedron::box_cut_by(b, nullptr, 0, 1e-12);
  EXPECT_EQ(P.face_count, 6);
  EXPECT_EQ(distinct(P, 1e-9).size(), 8u);
}

TEST(ConvexPolyhedron, CornerCutOfTheUnitCube) {
  // x + y + z >= 2.5 leaves the tetrahedron at (1,1,1) with corners (0.5,1,1), (1,0.5,1),
  // (1,1,0.5).
  const WorkspaceBox b{{0, 0, 0}, {1, 1, 1}};
  const HalfSpace3 cut{{1, 1, 1}, -2.5};
  const auto P = ConvexPolyhedron::box_cut_by(b, &cut, 1, 1e-12);
  const auto v = distinct(P, 1e-9);
  ASSERT_EQ(v.size(), 4u);
  for (const auto& x : v) EXPECT_NEAR(x.sum(), x == Eigen::Vector3d(1, 1, 1) ? 3.0 : 2.5, 1e-12);
}

TEST(ConvexPolyhedron, DisjointCutIsEmpty) {
  const WorkspaceBox b{{0, 0, 0}, {1, 1, 1}};
  const HalfSpace3 cut{{1, 0, 0}, -2};  // x >= 2
  EXPECT_TRUE(ConvexPolyhedron::box_cut_by(b, &cut, 1, 1e-12).empty());
}

TEST(ConvexPolyhedron, FlatBoxKeepsItsSlice) {
  // A zero-thickness box z = 0.5 cut by x <= 0.25: the rectangle [0,0.25] x [0,1] at z = 0.5.
  const WorkspaceBox b{{0, 0, 0.5}, {1, 1, 0.5}};
  const HalfSpace3 cut{{-1, 0, 0.3}, 0.25 - 0.15};  // -x + 0.3 z + 0.1 >= 0 <=> x <= 0.25 at z=0.5
  const auto v = distinct(ConvexPolyhedron::box_cut_by(b, &cut, 1, 1e-12), 1e-9);
  ASSERT_EQ(v.size(), 4u);
  for (const auto& x : v) {
    EXPECT_NEAR(x.z(), 0.5, 1e-12);
    EXPECT_TRUE(std::abs(x.x()) < 1e-9 || std::abs(x.x() - 0.25) < 1e-9) << x.transpose();
  }
}

TEST(ConvexPolyhedron, InvalidInputIsEmpty) {
  const WorkspaceBox inverted{{0, 0, 1}, {1, 1, 0}};
  EXPECT_TRUE(ConvexPolyhedron::box_cut_by(inverted, nullptr, 0, 1e-12).empty());
  const WorkspaceBox nan_box{{0, 0, NAN}, {1, 1, 1}};
  EXPECT_TRUE(ConvexPolyhedron::box_cut_by(nan_box, nullptr, 0, 1e-12).empty());
}

RC_GTEST_PROP(ConvexPolyhedron, VerticesMatchPlaneTripleEnumeration, ()) {
  auto coord = [] { return *rc::gen::inRange(-1000, 1000) / 1000.0; };
  WorkspaceBox b;
  for (int a = 0; a < 3; ++a) {
    const double x = coord();
    const double y = coord();
    b.min_m[a] = std::min(x, y) - 0.05;
    b.max_m[a] = std::max(x, y) + 0.05;
  }
  const int n = *rc::gen::inRange(1, ConvexPolyhedron::kMaxCuts + 1);
  std::vector<HalfSpace3> cuts;
  const Eigen::Vector3d centre = 0.5 * (b.min_m + b.max_m);
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d nrm(coord(), coord(), coord());
    if (nrm.norm() < 0.1) nrm = Eigen::Vector3d(0.3, -0.2, 1.0);
    // Planes through points near the box centre so most cuts really cut.
    const Eigen::Vector3d p = centre + 0.3 * Eigen::Vector3d(coord(), coord(), coord());
    cuts.push_back(HalfSpace3::through(p, nrm));
  }
  const auto P = ConvexPolyhedron::box_cut_by(b, cuts.data(), n, 1e-12);
  for (int i = 0; i < P.face_count; ++i) RC_ASSERT(!P.faces[i].overflowed());
  const auto ours = distinct(P, 1e-7);
  const auto ref = enumerate_vertices(b, cuts, 1e-9);
  // Every true vertex is found...
  for (const auto& r : ref) {
    bool found = false;
    for (const auto& o : ours) found = found || (o - r).norm() < 1e-6;
    RC_ASSERT(found);
  }
  // ...and every vertex found is a true vertex (or within rounding of one).
  for (const auto& o : ours) {
    bool found = false;
    for (const auto& r : ref) found = found || (o - r).norm() < 1e-6;
    RC_ASSERT(found);
  }
}
