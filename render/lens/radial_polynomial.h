#pragma once
// The lens's radial polynomial P(r) = sum k_i r^i, its derivative and where it stops increasing.

#include <cmath>
#include <span>

namespace hd::render::lens {

/// Horner evaluation of P and P'; r in the profile's r units.
struct RadialPolynomial {
  std::span<const double> k;

  double value(double r) const {
    double s = 0.0;
    for (std::size_t i = k.size(); i-- > 0;) s = s * r + k[i];
    return s;
  }
  double derivative(double r) const {
    double s = 0.0;
    for (std::size_t i = k.size(); i-- > 1;) s = s * r + static_cast<double>(i) * k[i];
    return s;
  }
  /// P(r) / r, continued to P'(0) at r = 0: the scale from panel offset to eye-image offset.
  double ratio(double r) const {
    if (r <= 0.0) return k.size() > 1 ? k[1] : 0.0;
    return value(r) / r;
  }
  /// The smallest r in [0, r_max] with P'(r) <= 0 (stepped at 1e-4 and refined by bisection),
  /// or a negative number when P increases strictly on the whole interval.
  double first_non_increasing(double r_max) const {
    constexpr double kStep = 1e-4;
    double lo = 0.0;
    for (double r = 0.0; r <= r_max + kStep; r += kStep) {
      const double x = std::fmin(r, r_max);
      if (derivative(x) <= 0.0) {
        double hi = x;
        for (int i = 0; i < 40; ++i) {
          const double mid = 0.5 * (lo + hi);
          (derivative(mid) <= 0.0 ? hi : lo) = mid;
        }
        return hi;
      }
      lo = x;
      if (x >= r_max) break;
    }
    return -1.0;
  }
};

}  // namespace hd::render::lens
