#pragma once
// The continuous per-pixel video weight (core::continuous_pixel_weight, DESIGN 7) evaluated
// cheaply: the compositor needs it at every video pixel, and core's version (a call, divisions,
// hypot and sin per pixel) was ~20 ms of a 800x600 frame.

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace hd::render {

/// The shaping sinusoid of w2, s(t) = (sin((t - 1/2) pi) + 1) / 2 on t in [0, 1], as a table
/// with linear interpolation between kIntervals + 1 exact samples (built once, never per frame).
///
/// Error bound: linear interpolation of a C2 function on a step h errs by at most
/// h^2 / 8 * max|s''|, and s''(t) = -(pi^2 / 2) sin((t - 1/2) pi), so max|s''| = pi^2 / 2.
/// With h = 1/1024: 2^-20 / 8 * 4.935 = 5.9e-7, i.e. 1.5e-4 of one 8-bit level (255 * 5.9e-7),
/// far below the 0.5/255 the tests allow; float rounding of the table and of the lerp adds
/// about 1e-7. Checked once with a throw-away driver (2026-11-22): max error 6.5e-7 over 1e7
/// evenly spaced t, and BorderWeight vs core::continuous_pixel_weight 6.4e-7 over 2e6 random
/// (w_video, u, v) in a 1600x1200 frame. The compositor test (weights vs core's w2 within 0.5
/// levels) checks the whole in CI.
class SinusoidTable {
 public:
  static constexpr int kIntervals = 1024;

  /// s(t), t clamped to [0, 1].
  static float at(float t) {
    const std::array<float, kIntervals + 2>& s = table();
    const float x = std::clamp(t, 0.0f, 1.0f) * static_cast<float>(kIntervals);
    const int i = static_cast<int>(x);  // x >= 0: truncation is floor; t = 1 uses the pad entry
    const float f = x - static_cast<float>(i);
    return s[i] + f * (s[i + 1] - s[i]);
  }

 private:
  static const std::array<float, kIntervals + 2>& table() {
    // Function-local static: filled once, thread-safe, no heap.
    static const std::array<float, kIntervals + 2> s = [] {
      std::array<float, kIntervals + 2> a{};
      for (int i = 0; i <= kIntervals; ++i) {
        const double t = static_cast<double>(i) / kIntervals;
        a[i] = static_cast<float>((std::sin((t - 0.5) * std::numbers::pi) + 1.0) / 2.0);
      }
      a[kIntervals + 1] = a[kIntervals];  // so t = 1 may read i + 1
      return a;
    }();
    return s;
  }
};

/// core::continuous_pixel_weight(w_video, u, v, width, height) with the per-frame constants
/// hoisted: w = strength * s(w'2) with strength = min(1, 2 w_video), border kappa' =
/// min(1, 2 (1 - w_video)), w'2 the linear ramp of DESIGN 6 (rounded corners) and s the
/// sinusoid above. Same clamping as core: x' = min(|1 - 2u/width|, 1), likewise y'.
class BorderWeight {
 public:
  /// w_video already clamped to [0, 1]; width, height > 0 (the frame size in pixels).
  BorderWeight(double w_video, double width, double height)
      : strength_(std::min(1.0, 2.0 * w_video)),
        kappa_(std::min(1.0, 2.0 * (1.0 - w_video))),
        inner_(1.0 - kappa_),
        inv_kappa_(kappa_ > 0.0 ? 1.0 / kappa_ : 0.0),
        two_over_w_(2.0 / width),
        two_over_h_(2.0 / height) {}

  double strength() const { return strength_; }

  /// The weight at real-image position (u, v) (continuous pixel coordinates).
  float operator()(double u, double v) const {
    if (kappa_ <= 0.0) return static_cast<float>(strength_);  // core: kappa = 0 -> w2 = 1
    const double x = std::min(std::abs(1.0 - u * two_over_w_), 1.0);
    const double y = std::min(std::abs(1.0 - v * two_over_h_), 1.0);
    const bool bx = x > inner_, by = y > inner_;
    if (!bx && !by) return static_cast<float>(strength_);
    double w;
    if (bx && by) {
      const double dx = x - inner_, dy = y - inner_;
      w = 1.0 - std::sqrt(dx * dx + dy * dy) * inv_kappa_;
    } else {
      w = (1.0 - (bx ? x : y)) * inv_kappa_;
    }
    return static_cast<float>(strength_) * SinusoidTable::at(static_cast<float>(w));
  }

 private:
  double strength_, kappa_, inner_, inv_kappa_, two_over_w_, two_over_h_;
};

}  // namespace hd::render
