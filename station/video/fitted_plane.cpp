#include "station/video/fitted_plane.h"

#include <algorithm>
#include <cmath>

namespace hd::station {

namespace {
constexpr double kNear_m = 0.05, kFar_m = 100.0;
}

FittedPlane::FittedPlane(const core::Pinhole& camera, double d_m) : d_m_(d_m), target_m_(NAN) {
  set_camera(camera);
}

void FittedPlane::set_camera(const core::Pinhole& camera) {
  camera_ = camera;
  map_camera_ = camera;
  if (!camera.valid()) return;  // not calibrated yet (a network camera before its stream's)
  map_camera_.width = std::max(1, camera.width / kMapScale);
  map_camera_.height = std::max(1, camera.height / kMapScale);
  // Pixel centres stay where they are: continuous coordinates scale with the size.
  map_camera_.fx = camera.fx * map_camera_.width / camera.width;
  map_camera_.fy = camera.fy * map_camera_.height / camera.height;
  map_camera_.cx = camera.cx * map_camera_.width / camera.width;
  map_camera_.cy = camera.cy * map_camera_.height / camera.height;
  depths_.resize(static_cast<std::size_t>(map_camera_.width) * map_camera_.height);
}

double FittedPlane::update(const render::SyntheticScene* scene, const core::Pose& T_world_cam,
                           const core::PixelRect* region, double dt_s) {
  if (scene == nullptr || !camera_.valid() || !map_camera_.valid()) return d_m_;
  map_.update(*scene, map_camera_, T_world_cam, kNear_m, kFar_m, nullptr);
  const int w = map_.width(), h = map_.height();
  const double sx = static_cast<double>(w) / camera_.width;
  const double sy = static_cast<double>(h) / camera_.height;
  // The region in map texels: every texel whose centre lies inside it.
  int x0 = 0, y0 = 0, x1 = w, y1 = h;
  if (region != nullptr) {
    x0 = std::clamp(static_cast<int>(std::ceil(region->u_min * sx - 0.5)), 0, w);
    y0 = std::clamp(static_cast<int>(std::ceil(region->v_min * sy - 0.5)), 0, h);
    x1 = std::clamp(static_cast<int>(std::floor(region->u_max * sx - 0.5)) + 1, x0, w);
    y1 = std::clamp(static_cast<int>(std::floor(region->v_max * sy - 0.5)) + 1, y0, h);
  }
  std::size_t n = 0;
  const float* iz = map_.data();
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const float v = iz[static_cast<std::size_t>(y) * w + x];
      if (v > 0.0f) depths_[n++] = 1.0f / v;
    }
  if (n == 0) return d_m_;
  auto mid = depths_.begin() + static_cast<long>(n / 2);
  std::nth_element(depths_.begin(), mid, depths_.begin() + static_cast<long>(n));
  target_m_ = *mid;
  if (!started_) {
    d_m_ = target_m_;
    started_ = true;
  } else if (dt_s > 0.0) {
    d_m_ += (target_m_ - d_m_) * (1.0 - std::exp(-std::min(dt_s, 1.0) / kTimeConstant_s));
  }
  return d_m_;
}

}  // namespace hd::station
