#include "render/compositor/camera_depth_map.h"

#include <algorithm>

#include "render/cpu/row_worker.h"

namespace hd::render {

namespace {
bool same_pinhole(const core::Pinhole& a, const core::Pinhole& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.width == b.width &&
         a.height == b.height;
}
}  // namespace

bool CameraDepthMap::update(const SyntheticScene& scene, const core::Pinhole& camera,
                            const core::Pose& T_world, double near_m, double far_m,
                            RowWorker* rows) {
  if (valid_ && scene_ == &scene && revision_ == scene.revision && same_pinhole(camera_, camera) &&
      pose_.R == T_world.R && pose_.t == T_world.t && near_m_ == near_m && far_m_ == far_m)
    return false;
  scene_ = &scene;
  revision_ = scene.revision;
  camera_ = camera;
  pose_ = T_world;
  near_m_ = near_m;
  far_m_ = far_m;
  valid_ = true;
  const std::size_t n = static_cast<std::size_t>(camera.width) * camera.height;
  inv_depth_.resize(n);
  std::fill(inv_depth_.begin(), inv_depth_.end(), 0.0f);
  rasterizer_.prepare(scene, camera, T_world, near_m, far_m);
  const RasterTarget target{nullptr, inv_depth_.data(), camera.width, camera.height};
  auto band = [&](int row_begin, int row_end, int) {
    rasterizer_.draw_rows(scene, target, row_begin, row_end);
  };
  if (rows != nullptr)
    rows->run(camera.height, band);
  else
    band(0, camera.height, 0);
  ++renders_;
  return true;
}

}  // namespace hd::render
