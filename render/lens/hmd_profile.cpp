#include "render/lens/hmd_profile.h"

#include <cmath>
#include <cstdio>

#include "render/lens/lens_warp.h"
#include "render/lens/radial_polynomial.h"

namespace hd::render::lens {
namespace {

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string pair(const Eigen::Vector2d& v) {
  return "[" + num(v.x()) + ", " + num(v.y()) + "]";
}

bool positive(double v) {
  return std::isfinite(v) && v > 0.0;
}

}  // namespace

std::optional<ProfileProblem> check_profile(const HmdProfile& p) {
  if (p.neutral) return std::nullopt;
  if (p.panel_width_px < 2 || p.panel_width_px > 16384 || p.panel_width_px % 2 != 0)
    return ProfileProblem{"panel.width_px", std::to_string(p.panel_width_px),
                          "expected an even number of pixels in [2, 16384] (two eyes)"};
  if (p.panel_height_px < 1 || p.panel_height_px > 16384)
    return ProfileProblem{"panel.height_px", std::to_string(p.panel_height_px),
                          "expected [1, 16384] pixels"};
  if (!positive(p.panel_width_m) || p.panel_width_m > 1.0)
    return ProfileProblem{"panel.width_m", num(p.panel_width_m), "expected (0, 1] metres"};
  if (!positive(p.panel_height_m) || p.panel_height_m > 1.0)
    return ProfileProblem{"panel.height_m", num(p.panel_height_m), "expected (0, 1] metres"};
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector2d& c = p.lens_centre_m[static_cast<std::size_t>(e)];
    if (!(c.x() >= 0.0 && c.x() <= p.eye_panel_width_m() && c.y() >= 0.0 &&
          c.y() <= p.panel_height_m))
      return ProfileProblem{e == 0 ? "lens_centre_m.left" : "lens_centre_m.right", pair(c),
                            "off the eye's half of the panel ([0, " + num(p.eye_panel_width_m()) +
                                "] x [0, " + num(p.panel_height_m) + "] m)"};
  }
  if (!positive(p.r_unit_m.x()) || !positive(p.r_unit_m.y()))
    return ProfileProblem{"distortion.r_unit_m", pair(p.r_unit_m), "expected positive metres"};
  if (p.coefficients.size() < 2 || p.coefficients.size() > 12)
    return ProfileProblem{"distortion.coefficients", std::to_string(p.coefficients.size()),
                          "expected 2 to 12 coefficients"};
  for (double k : p.coefficients)
    if (!std::isfinite(k))
      return ProfileProblem{"distortion.coefficients", num(k), "not a finite number"};
  if (p.coefficients[0] != 0.0)
    return ProfileProblem{"distortion.coefficients[0]", num(p.coefficients[0]),
                          "must be 0: the lens maps its centre to the eye's centre"};
  if (!(p.coefficients[1] > 0.0))
    return ProfileProblem{"distortion.coefficients[1]", num(p.coefficients[1]),
                          "P'(0) must be > 0"};
  if (!(p.max_radius >= 0.0) || !std::isfinite(p.max_radius))
    return ProfileProblem{"distortion.max_radius", num(p.max_radius), "expected >= 0"};
  for (std::size_t c = 0; c < 3; ++c)
    if (!(p.aberration[c] >= 0.5 && p.aberration[c] <= 2.0))
      return ProfileProblem{"aberration[" + std::to_string(c) + "]", num(p.aberration[c]),
                            "expected a scale in [0.5, 2]"};
  if (p.fov_deg) {
    for (int i = 0; i < 2; ++i) {
      const double f = (*p.fov_deg)[i];
      if (!(f > 0.0 && f < 180.0))
        return ProfileProblem{i == 0 ? "fov_deg[0]" : "fov_deg[1]", num(f),
                              "a field of view must be in (0, 180) degrees"};
    }
  } else if (!positive(p.eye_to_screen_m) || p.eye_to_screen_m > 1.0) {
    return ProfileProblem{"eye_to_screen_m", num(p.eye_to_screen_m),
                          "expected (0, 1] metres (or give fov_deg)"};
  }
  if (p.swap_to_photon_ms && !(*p.swap_to_photon_ms >= 0.0 && *p.swap_to_photon_ms <= 100.0))
    return ProfileProblem{"swap_to_photon_ms", num(*p.swap_to_photon_ms), "expected [0, 100] ms"};

  // Monotonic over every radius the panel uses: otherwise two panel radii show the same ray and
  // the picture folds over itself. The radius the panel reaches is at a corner of a half.
  double r_panel = 0.0;
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector2d& c = p.lens_centre_m[static_cast<std::size_t>(e)];
    for (double x : {0.0, p.eye_panel_width_m()})
      for (double y : {0.0, p.panel_height_m})
        r_panel = std::max(r_panel,
                           std::hypot((x - c.x()) / p.r_unit_m.x(), (y - c.y()) / p.r_unit_m.y()));
  }
  const double r_used = p.max_radius > 0.0 ? std::min(p.max_radius, r_panel) : r_panel;
  const RadialPolynomial poly{p.coefficients};
  const double r_fold = poly.first_non_increasing(r_used);
  if (r_fold >= 0.0)
    return ProfileProblem{"distortion.coefficients", "P'(" + num(r_fold) + ") <= 0",
                          "the polynomial is not increasing up to the radius the panel uses (" +
                              num(r_used) + "); set distortion.max_radius below " + num(r_fold) +
                              " to black out the panel beyond it"};

  const LensWarp warp(p);
  if (warp.eye_width() > 8192 || warp.eye_height() > 8192)
    return ProfileProblem{"distortion",
                          std::to_string(warp.eye_width()) + "x" +
                              std::to_string(warp.eye_height()) + " px eye image",
                          "the eye image the lens needs exceeds 8192 px; set "
                          "distortion.max_radius"};
  const double fx = warp.eye_fov_x_deg(), fy = warp.eye_fov_y_deg();
  if (!(fx < 180.0 && fy < 180.0))
    return ProfileProblem{"fov_deg", num(fx) + " x " + num(fy), "eye field of view >= 180"};
  return std::nullopt;
}

}  // namespace hd::render::lens
