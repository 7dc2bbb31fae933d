#pragma once
// A closed half-space {p : n.p + c >= 0} in 2D or 3D, the building block of every clip in core.

#include <Eigen/Core>

namespace hd::core {

template <int Dim>
struct HalfSpace {
  using Vec = Eigen::Matrix<double, Dim, 1>;
  Vec n =
      Vec::Zero();  ///< normal pointing inside; unit length when built by `through`/`normalized`
  double c = 0.0;

  double signed_distance(const Vec& p) const { return n.dot(p) + c; }

  /// Unit normal, so signed distances are metric and one tolerance fits every plane.
  HalfSpace normalized() const {
    const double len = n.norm();
    return len > 0.0 ? HalfSpace{n / len, c / len} : *this;
  }

  /// The half-space with inward normal `n` whose boundary passes through `p`.
  static HalfSpace through(const Vec& p, const Vec& n) {
    const HalfSpace h{n, -n.dot(p)};
    return h.normalized();
  }
};

using HalfSpace2 = HalfSpace<2>;
using HalfSpace3 = HalfSpace<3>;

}  // namespace hd::core
