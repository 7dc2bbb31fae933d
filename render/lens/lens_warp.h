#pragma once
// The exact panel -> eye-image mapping of one HMD profile, and the eye images it needs.

#include <array>

#include "core/pinhole.h"
#include "render/compositor/viewport.h"
#include "render/lens/hmd_profile.h"
#include "render/lens/radial_polynomial.h"

namespace hd::render::lens {

/// Built once from a checked HmdProfile. The two eye images lie side by side in one picture (the
/// StereoRig layout: left at x = 0, right at x = eye_width); the panel is panel_width x
/// panel_height, each eye's half showing its eye through the lens.
///
/// Eye image geometry: at the lens centre one eye pixel covers one panel pixel (the green
/// channel's pitch there is P'(0) * aberration[G] * the panel pitch), and the image is just large
/// enough that every panel pixel inside the usable radius samples inside it, for R, G and B (plus
/// a one-pixel border for the bilinear neighbours). Its pinhole: u = cx + q_src.x / pitch, with
/// fx = eye_to_screen / pitch, or from the published field of view (see HmdProfile).
class LensWarp {
 public:
  LensWarp() = default;
  explicit LensWarp(const HmdProfile& profile);

  const HmdProfile& profile() const { return profile_; }
  int panel_width() const { return profile_.panel_width_px; }
  int panel_height() const { return profile_.panel_height_px; }
  int eye_panel_width() const { return profile_.eye_panel_width_px(); }
  int eye_width() const { return eye_w_; }
  int eye_height() const { return eye_h_; }
  /// p_o of eye i (0 left, 1 right), in that eye's own image coordinates.
  const core::Pinhole& eye(int i) const { return eye_[static_cast<std::size_t>(i)]; }
  /// Horizontal and vertical field of view of the eye image, degrees (what the station renders).
  double eye_fov_x_deg() const;
  double eye_fov_y_deg() const;

  /// Lens radius (r units) of the panel point (x, y) in eye i's half (continuous half
  /// coordinates, pixel centres at +0.5).
  double radius(int eye, double x, double y) const;
  /// Where the panel point (x, y) of eye i's half samples the eye image for channel c (0 R, 1 G,
  /// 2 B), in eye i's own image coordinates. False (and u, v untouched) outside the usable radius.
  bool source(int eye, double x, double y, int channel, double* u, double* v) const;
  /// The same without the usable-radius test (the polynomial continued beyond it): for the
  /// vertices of a distortion mesh whose triangles straddle the rim.
  void source_unclamped(int eye, double x, double y, int channel, double* u, double* v) const;

  /// Green-relative scale of channel c: its sample lies at centre + scale * (green - centre).
  double channel_scale(int c) const {
    return profile_.aberration[static_cast<std::size_t>(c)] / profile_.aberration[1];
  }
  /// The part of eye i's image (its own coordinates) comfortably seen through the lens: the
  /// extent of the panel's usable axes through the lens centre, shrunk to 70 % about the
  /// principal point (a rectangle inscribed in a disc spans 71 % of its axes). For the HUD.
  Viewport visible_rect(int eye) const;
  /// The largest lens radius any panel pixel of either half has (before max_radius).
  double panel_max_radius() const { return panel_max_r_; }

  /// source_unclamped() in panel pixels, for evaluating it in bulk (CpuPredistorter): for the
  /// half point (x, y) of eye i, with d = (x, y) - centre_px, the radius is
  /// r = |(d.x * r_per_px.x, d.y * r_per_px.y)| and channel c samples the eye image at
  /// (cx, cy) + ratio(r) * (gain[c].x * d.x, gain[c].y * d.y), ratio(r) = P(r) / r.
  struct PanelMap {
    Eigen::Vector2d centre_px{0.0, 0.0};    ///< lens centre, half coordinates
    Eigen::Vector2d r_per_px{0.0, 0.0};     ///< r units per panel pixel
    std::array<Eigen::Vector2d, 3> gain{};  ///< eye-image px per panel px per unit ratio
  };
  PanelMap panel_map(int eye) const;

 private:
  HmdProfile profile_;
  RadialPolynomial poly_;
  double eye_pitch_x_ = 1.0, eye_pitch_y_ = 1.0;  ///< undistorted metres per eye pixel
  int eye_w_ = 0, eye_h_ = 0;
  std::array<core::Pinhole, 2> eye_{};
  double panel_max_r_ = 0.0;
};

}  // namespace hd::render::lens
