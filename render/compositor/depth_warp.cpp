#include "render/compositor/depth_warp.h"

#include <algorithm>

namespace hd::render {

DepthWarp DepthWarp::make(const core::Pinhole& eye, const core::Pose& T_world_eye,
                          const core::Pinhole& real, const core::Pose& T_world_real) {
  DepthWarp w;
  if (!eye.valid() || !real.valid() || !T_world_eye.valid() || !T_world_real.valid()) return w;
  // X_real = R X_eye + t with X_eye = z_eye K_o^-1 p, so K_c X_real / z_eye = A p + b / z_eye.
  const core::Pose T_real_eye = T_world_real.inverse() * T_world_eye;
  Eigen::Matrix3d K_o_inv;
  K_o_inv << 1.0 / eye.fx, 0, -eye.cx / eye.fx, 0, 1.0 / eye.fy, -eye.cy / eye.fy, 0, 0, 1;
  Eigen::Matrix3d K_c;
  K_c << real.fx, 0, real.cx, 0, real.fy, real.cy, 0, 0, 1;
  w.A = K_c * T_real_eye.R * K_o_inv;
  w.b = K_c * T_real_eye.t;
  w.usable = w.A.allFinite() && w.b.allFinite();
  return w;
}

void depth_warp_row(const DepthRow& w, int n, const float* eye_iz, float* u, float* v, float* a,
                    float* real_iz) {
  for (int x = 0; x < n; ++x) {
    const double px = x + 0.5;
    double iz = eye_iz[x];
    const bool model = iz > 0.0;
    if (!model) iz = w.q0 * px + w.bz;
    u[x] = v[x] = a[x] = real_iz[x] = 0.0f;
    if (!(iz > 0.0) || iz > w.inv_near) continue;
    const double hw = w.a20 * px + w.cw + w.b2 * iz;
    if (!(hw > 0.0)) continue;
    const double s = 1.0 / hw;
    const double uu = (w.a00 * px + w.cx + w.b0 * iz) * s;
    const double vv = (w.a10 * px + w.cy + w.b1 * iz) * s;
    if (!(uu >= 0.0 && vv >= 0.0 && uu <= w.width && vv <= w.height)) continue;
    u[x] = static_cast<float>(uu);
    v[x] = static_cast<float>(vv);
    a[x] = w.weight;
    if (model && w.seen != nullptr) real_iz[x] = static_cast<float>(iz * s);
  }
}

void seen_test_row(const DepthRow& w, int x_begin, int x_end, const float* u, const float* v,
                   const float* real_iz, float* a) {
  for (int x = x_begin; x < x_end; ++x) {
    if (!(real_iz[x] > 0.0f)) continue;
    const int sx = std::min(static_cast<int>(u[x]), w.seen_width - 1);
    const int sy = std::min(static_cast<int>(v[x]), w.seen_height - 1);
    if (!seen_by_real(real_iz[x], w.seen[static_cast<long>(sy) * w.seen_width + sx])) a[x] = 0.0f;
  }
}

}  // namespace hd::render
