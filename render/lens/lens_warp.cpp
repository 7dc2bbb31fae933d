#include "render/lens/lens_warp.h"

#include <algorithm>
#include <cmath>

namespace hd::render::lens {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance e with atan(a / e) + atan(b / e) = angle (a, b >= 0, a + b > 0, 0 < angle < pi):
// the left side falls from pi (e -> 0) to 0 (e -> inf), so bisection on log e.
double distance_for_fov(double a, double b, double angle) {
  double lo = 1e-9, hi = 1e3;
  for (int i = 0; i < 200; ++i) {
    const double mid = std::sqrt(lo * hi);
    const double f = std::atan(a / mid) + std::atan(b / mid);
    (f > angle ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

}  // namespace

LensWarp::LensWarp(const HmdProfile& profile) : profile_(profile) {
  poly_.k = profile_.coefficients;
  const double k1 = poly_.ratio(0.0);
  eye_pitch_x_ = k1 * profile_.aberration[1] * profile_.pitch_x_m();
  eye_pitch_y_ = k1 * profile_.aberration[1] * profile_.pitch_y_m();

  // Extent of every sample (all channels) in undistorted metres around each lens centre.
  std::array<double, 2> min_x{0, 0}, max_x{0, 0}, min_y{0, 0}, max_y{0, 0};
  const int hw = eye_panel_width(), h = panel_height();
  for (int e = 0; e < 2; ++e) {
    const Eigen::Vector2d& lc = profile_.lens_centre_m[static_cast<std::size_t>(e)];
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < hw; ++x) {
        const double qx = (x + 0.5) * profile_.pitch_x_m() - lc.x();
        const double qy = (y + 0.5) * profile_.pitch_y_m() - lc.y();
        const double r = std::hypot(qx / profile_.r_unit_m.x(), qy / profile_.r_unit_m.y());
        panel_max_r_ = std::max(panel_max_r_, r);
        if (profile_.max_radius > 0.0 && r > profile_.max_radius) continue;
        const double f = poly_.ratio(r);
        for (double s : profile_.aberration) {
          const std::size_t i = static_cast<std::size_t>(e);
          min_x[i] = std::min(min_x[i], s * f * qx);
          max_x[i] = std::max(max_x[i], s * f * qx);
          min_y[i] = std::min(min_y[i], s * f * qy);
          max_y[i] = std::max(max_y[i], s * f * qy);
        }
      }
    }
  }
  // One size for both eyes; each keeps its own principal point (the lenses are mirrored).
  std::array<double, 2> left_px{}, top_px{};
  double w = 0.0, hh = 0.0;
  for (std::size_t e = 0; e < 2; ++e) {
    left_px[e] = -min_x[e] / eye_pitch_x_ + 1.0;
    top_px[e] = -min_y[e] / eye_pitch_y_ + 1.0;
    w = std::max(w, (max_x[e] - min_x[e]) / eye_pitch_x_ + 2.0);
    hh = std::max(hh, (max_y[e] - min_y[e]) / eye_pitch_y_ + 2.0);
  }
  eye_w_ = static_cast<int>(std::ceil(w));
  eye_h_ = static_cast<int>(std::ceil(hh));

  // Focal lengths: tan(angle) = q_src / distance, u = cx + q_src / pitch.
  double dist_x = profile_.eye_to_screen_m, dist_y = profile_.eye_to_screen_m;
  if (profile_.fov_deg) {
    const Eigen::Vector2d& lc = profile_.lens_centre_m[0];
    dist_x = distance_for_fov(lc.x(), profile_.eye_panel_width_m() - lc.x(),
                              profile_.fov_deg->x() * kPi / 180.0);
    dist_y = distance_for_fov(lc.y(), profile_.panel_height_m - lc.y(),
                              profile_.fov_deg->y() * kPi / 180.0);
  }
  for (std::size_t e = 0; e < 2; ++e) {
    core::Pinhole& k = eye_[e];
    k.width = eye_w_;
    k.height = eye_h_;
    k.fx = dist_x / eye_pitch_x_;
    k.fy = dist_y / eye_pitch_y_;
    k.cx = left_px[e];
    k.cy = top_px[e];
  }
}

double LensWarp::eye_fov_x_deg() const {
  const core::Pinhole& k = eye_[0];
  return (std::atan(k.cx / k.fx) + std::atan((k.width - k.cx) / k.fx)) * 180.0 / kPi;
}

double LensWarp::eye_fov_y_deg() const {
  const core::Pinhole& k = eye_[0];
  return (std::atan(k.cy / k.fy) + std::atan((k.height - k.cy) / k.fy)) * 180.0 / kPi;
}

Viewport LensWarp::visible_rect(int eye) const {
  const Eigen::Vector2d& lc = profile_.lens_centre_m[static_cast<std::size_t>(eye)];
  const double x0 = lc.x() / profile_.pitch_x_m(), y0 = lc.y() / profile_.pitch_y_m();
  const core::Pinhole& k = eye_[static_cast<std::size_t>(eye)];
  // Farthest usable panel point along each axis direction, and where it samples (green).
  double lo[2] = {k.cx, k.cy}, hi[2] = {k.cx, k.cy};
  const double dirs[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  for (const auto& d : dirs) {
    for (double t = 0.0;; t += 1.0) {
      const double x = x0 + d[0] * t, y = y0 + d[1] * t;
      if (x < 0.5 || x > eye_panel_width() - 0.5 || y < 0.5 || y > panel_height() - 0.5) break;
      double u = 0, v = 0;
      if (!source(eye, x, y, 1, &u, &v)) break;
      lo[0] = std::min(lo[0], u), hi[0] = std::max(hi[0], u);
      lo[1] = std::min(lo[1], v), hi[1] = std::max(hi[1], v);
    }
  }
  constexpr double kShrink = 0.7;
  const int x_begin = static_cast<int>(std::ceil(k.cx - kShrink * (k.cx - lo[0])));
  const int x_end = static_cast<int>(std::floor(k.cx + kShrink * (hi[0] - k.cx)));
  const int y_begin = static_cast<int>(std::ceil(k.cy - kShrink * (k.cy - lo[1])));
  const int y_end = static_cast<int>(std::floor(k.cy + kShrink * (hi[1] - k.cy)));
  return {x_begin, y_begin, std::max(1, x_end - x_begin), std::max(1, y_end - y_begin)};
}

LensWarp::PanelMap LensWarp::panel_map(int eye) const {
  const Eigen::Vector2d& lc = profile_.lens_centre_m[static_cast<std::size_t>(eye)];
  PanelMap m;
  m.centre_px = {lc.x() / profile_.pitch_x_m(), lc.y() / profile_.pitch_y_m()};
  m.r_per_px = {profile_.pitch_x_m() / profile_.r_unit_m.x(),
                profile_.pitch_y_m() / profile_.r_unit_m.y()};
  for (std::size_t c = 0; c < 3; ++c)
    m.gain[c] = {profile_.aberration[c] * profile_.pitch_x_m() / eye_pitch_x_,
                 profile_.aberration[c] * profile_.pitch_y_m() / eye_pitch_y_};
  return m;
}

double LensWarp::radius(int eye, double x, double y) const {
  const Eigen::Vector2d& lc = profile_.lens_centre_m[static_cast<std::size_t>(eye)];
  const double qx = x * profile_.pitch_x_m() - lc.x();
  const double qy = y * profile_.pitch_y_m() - lc.y();
  return std::hypot(qx / profile_.r_unit_m.x(), qy / profile_.r_unit_m.y());
}

bool LensWarp::source(int eye, double x, double y, int channel, double* u, double* v) const {
  if (profile_.max_radius > 0.0 && radius(eye, x, y) > profile_.max_radius) return false;
  source_unclamped(eye, x, y, channel, u, v);
  return true;
}

void LensWarp::source_unclamped(int eye, double x, double y, int channel, double* u,
                                double* v) const {
  const Eigen::Vector2d& lc = profile_.lens_centre_m[static_cast<std::size_t>(eye)];
  const double qx = x * profile_.pitch_x_m() - lc.x();
  const double qy = y * profile_.pitch_y_m() - lc.y();
  const double r = std::hypot(qx / profile_.r_unit_m.x(), qy / profile_.r_unit_m.y());
  const double s = profile_.aberration[static_cast<std::size_t>(channel)] * poly_.ratio(r);
  const core::Pinhole& k = eye_[static_cast<std::size_t>(eye)];
  *u = k.cx + s * qx / eye_pitch_x_;
  *v = k.cy + s * qy / eye_pitch_y_;
}

}  // namespace hd::render::lens
