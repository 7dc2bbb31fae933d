#pragma once
// An HMD profile: the panel, the lenses and the eye geometry a head-mounted display needs, as data.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace hd::render::lens {

/// What the station needs to know about one HMD (file format: docs/hmd.md). All lengths in
/// metres, angles in degrees, panel coordinates x right, y down from each eye's half's top-left.
///
/// The panel is split into two halves side by side, the left eye's at x = 0. A panel point at
/// offset q (metres) from its eye's lens centre has the lens radius
///   r = |(q.x / r_unit_m.x, q.y / r_unit_m.y)|
/// and the lens shows there the eye image's undistorted point at offset
///   q_src(c) = aberration[c] * (P(r) / r) * q,   P(r) = sum_i coefficients[i] r^i
/// (the panotools / OpenHMD / OSVR convention: screen radius -> texture radius; OpenHMD's
/// "universal distortion" a, b, c, d is coefficients = {0, d, c, b, a}).
///
/// `neutral` is the monitor case: no lens, nothing is pre-distorted, the eyes are drawn as the
/// station's `display` section says.
struct HmdProfile {
  std::string name;    ///< e.g. "oculus-dk1"
  std::string source;  ///< where the numbers come from
  bool neutral = true;
  int panel_width_px = 0;  ///< both eyes
  int panel_height_px = 0;
  double panel_width_m = 0.0;
  double panel_height_m = 0.0;
  std::array<Eigen::Vector2d, 2> lens_centre_m{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  std::vector<double> coefficients;  ///< P(r) = sum coefficients[i] r^i, coefficients[0] = 0
  Eigen::Vector2d r_unit_m{1.0, 1.0};
  /// Usable lens radius (in r units): the panel beyond it is black. 0 = the whole panel.
  double max_radius = 0.0;
  std::array<double, 3> aberration{1.0, 1.0, 1.0};  ///< R, G, B scale of q_src
  /// The eye image's undistorted plane lies at this distance from the eye: tan(angle) = q / d.
  double eye_to_screen_m = 0.0;
  /// Published field of view of one eye's half of the panel, undistorted (horizontal, vertical);
  /// when given it sets the eye's focal lengths instead of eye_to_screen_m.
  std::optional<Eigen::Vector2d> fov_deg;
  std::optional<double> swap_to_photon_ms;  ///< panel latency after the swap, if published

  int eye_panel_width_px() const { return panel_width_px / 2; }
  double eye_panel_width_m() const { return panel_width_m / 2.0; }
  double pitch_x_m() const { return panel_width_m / panel_width_px; }
  double pitch_y_m() const { return panel_height_m / panel_height_px; }

  /// The neutral profile (no lens).
  static HmdProfile make_neutral() {
    HmdProfile p;
    p.name = "neutral";
    p.source = "no lens (a monitor)";
    return p;
  }
};

/// Why a profile cannot be used: the field (as spelt in the file), its value, the reason.
struct ProfileProblem {
  std::string field;
  std::string value;
  std::string why;
};

/// Checks every value of a non-neutral profile: sizes positive, lens centres on their eye's half,
/// coefficients[0] = 0 and P'(0) > 0, P(r) strictly increasing over every radius the panel uses
/// (up to max_radius if set), aberration scales in [0.5, 2], the field of view in (0, 180) and
/// the eye image no larger than 8192 px. The first problem found, or none.
std::optional<ProfileProblem> check_profile(const HmdProfile& p);

}  // namespace hd::render::lens
