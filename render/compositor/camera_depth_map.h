#pragma once
// The model seen from a real camera: the depth map the model-depth view tests visibility
// against (a shadow map), re-rendered only when the model or the camera changes.

#include <cstdint>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "render/compositor/mesh_rasterizer.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::render {

class RowWorker;

/// 1 / z_real of the nearest model surface per pixel of the camera (0 = none), at the camera's
/// own size (one entry per frame pixel, row-major), drawn by MeshRasterizer's rules without
/// colour. update() re-renders only when the scene (pointer or revision), the intrinsics, the
/// pose or the clip planes differ from the last render; a render allocates only when the size
/// grows.
class CameraDepthMap {
 public:
  /// Brings the map up to date; true when it was re-rendered. `rows` (may be null) spreads the
  /// rows over the compositor's threads.
  bool update(const SyntheticScene& scene, const core::Pinhole& camera, const core::Pose& T_world,
              double near_m, double far_m, RowWorker* rows);
  const float* data() const { return inv_depth_.data(); }
  int width() const { return camera_.width; }
  int height() const { return camera_.height; }
  uint64_t renders() const { return renders_; }

 private:
  MeshRasterizer rasterizer_;
  std::vector<float> inv_depth_;
  const SyntheticScene* scene_ = nullptr;
  uint64_t revision_ = 0;
  core::Pinhole camera_;
  core::Pose pose_;
  double near_m_ = 0.0, far_m_ = 0.0;
  bool valid_ = false;
  uint64_t renders_ = 0;
};

}  // namespace hd::render
