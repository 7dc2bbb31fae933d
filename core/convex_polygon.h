#pragma once
// Fixed-capacity convex polygon in 2D or 3D with Sutherland-Hodgman clipping by half-spaces.
// Storage is a std::array, so clipping never allocates (the per-frame path depends on it).

#include <Eigen/Core>
#include <algorithm>
#include <array>

#include "core/half_space.h"

namespace hd::core {

template <int Dim, int MaxVerts>
class ConvexPolygon {
 public:
  using Vec = Eigen::Matrix<double, Dim, 1>;
  static constexpr int kCapacity = MaxVerts;

  ConvexPolygon() = default;

  /// Appends a vertex (polygon order). Returns false, and marks the polygon overflowed, when full.
  bool push_back(const Vec& p) {
    if (size_ >= MaxVerts) {
      overflowed_ = true;
      return false;
    }
    verts_[size_++] = p;
    return true;
  }

  int size() const { return size_; }
  bool empty() const { return size_ == 0; }
  const Vec& operator[](int i) const { return verts_[i]; }
  void clear() { size_ = 0; }
  /// True when a vertex was dropped for lack of capacity (a sizing bug; tests check it never is).
  bool overflowed() const { return overflowed_; }

  /// Keeps the part with signed distance >= -tol_m. Vertices within the tolerance count as inside,
  /// so a polygon lying in a boundary plane (a flat workspace) survives rounding.
  void clip(const HalfSpace<Dim>& h, double tol_m = 0.0) {
    if (size_ == 0) return;
    std::array<double, MaxVerts> dist;
    bool all_in = true;
    bool all_out = true;
    for (int i = 0; i < size_; ++i) {
      dist[i] = h.signed_distance(verts_[i]);
      const bool in = dist[i] >= -tol_m;
      all_in = all_in && in;
      all_out = all_out && !in;
    }
    if (all_in) return;
    if (all_out) {
      size_ = 0;
      return;
    }
    std::array<Vec, MaxVerts> out;
    int n = 0;
    auto emit = [&](const Vec& p) {
      if (n < MaxVerts) {
        out[n++] = p;
      } else {
        overflowed_ = true;
      }
    };
    for (int i = 0; i < size_; ++i) {
      const int j = (i + size_ - 1) % size_;  // previous vertex
      const bool in_i = dist[i] >= -tol_m;
      const bool in_j = dist[j] >= -tol_m;
      if (in_i != in_j) {
        // Crossing: the boundary point between the two; clamped so a vertex inside only by the
        // tolerance never extrapolates.
        const double t = std::clamp(dist[j] / (dist[j] - dist[i]), 0.0, 1.0);
        emit(verts_[j] + t * (verts_[i] - verts_[j]));
      }
      if (in_i) emit(verts_[i]);
    }
    std::copy(out.begin(), out.begin() + n, verts_.begin());
    size_ = n;
  }

  /// Signed shoelace area (2D only); counter-clockwise in (u right, v down) pixels is negative.
  double signed_area() const requires(Dim == 2) {
    double a2 = 0.0;
    for (int i = 0; i < size_; ++i) {
      const Vec& p = verts_[i];
      const Vec& q = verts_[(i + 1) % size_];
      a2 += p.x() * q.y() - q.x() * p.y();
    }
    return 0.5 * a2;
  }

 private:
  std::array<Vec, MaxVerts> verts_;  // Eigen leaves these uninitialised: no per-frame memset
  int size_ = 0;
  bool overflowed_ = false;
};

}  // namespace hd::core
