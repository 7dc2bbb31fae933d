#pragma once
// Shared test fixtures: the example rig and small helpers. Expected values in the tests are
// derived independently (closed forms, raster counts), never from the code under test.

#include <Eigen/Geometry>
#include <cmath>

#include "core/view_setup.h"

namespace hd::core::test {

inline Pinhole pinhole(double f, int w, int h) {
  return Pinhole::centred(f, w, h);
}

/// The issue #2 example: real 1600x1200 f=2000 at the origin, virtual 800x600 f=1000 at x=0.02,
/// d = 0.5, workspace [-0.5,0.5]^2 x [0.2,1.0].
inline ViewSetup example_setup() {
  ViewSetup s;
  s.real = pinhole(2000, 1600, 1200);
  s.virt = pinhole(1000, 800, 600);
  s.T_world_virt.t = {0.02, 0.0, 0.0};
  s.d_m = 0.5;
  s.near_m = 0.01;
  s.workspace = {{-0.5, -0.5, 0.2}, {0.5, 0.5, 1.0}};
  return s;
}

inline Eigen::Matrix3d rot(double yaw, double pitch, double roll) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

/// Independent raster estimate of coverage: for each sample at the centre of a step x step cell
/// of the virtual screen, cast the virtual ray, intersect it with the plane z_c = d (in front of
/// the virtual camera, z_o >= near) and test the hit against the real image rectangle. Calls
/// on_hit(u_real, v_real) for every covered sample. Returns the covered fraction.
template <class OnHit>
double raster_coverage(const ViewSetup& s, double step_px, OnHit&& on_hit) {
  const Eigen::Matrix3d Rr_t = s.T_world_real.R.transpose();
  const Eigen::Vector3d a = Rr_t * (s.T_world_virt.t - s.T_world_real.t);
  const Eigen::Matrix3d M = Rr_t * s.T_world_virt.R;
  long hit = 0;
  long total = 0;
  for (double v = step_px / 2; v < s.virt.height; v += step_px) {
    for (double u = step_px / 2; u < s.virt.width; u += step_px) {
      ++total;
      const Eigen::Vector3d r((u - s.virt.cx) / s.virt.fx, (v - s.virt.cy) / s.virt.fy, 1.0);
      const Eigen::Vector3d b = M * r;  // z_o = 1 along r, so the ray parameter is z_o
      if (b.z() == 0.0) continue;
      const double t = (s.d_m - a.z()) / b.z();
      if (!(t >= s.near_m)) continue;
      const Eigen::Vector3d X = a + t * b;
      const double ur = s.real.fx * X.x() / s.d_m + s.real.cx;
      const double vr = s.real.fy * X.y() / s.d_m + s.real.cy;
      if (ur >= 0 && ur <= s.real.width && vr >= 0 && vr <= s.real.height) {
        ++hit;
        on_hit(ur, vr);
      }
    }
  }
  return static_cast<double>(hit) / static_cast<double>(total);
}

inline double raster_coverage(const ViewSetup& s, double step_px) {
  return raster_coverage(s, step_px, [](double, double) {});
}

}  // namespace hd::core::test
