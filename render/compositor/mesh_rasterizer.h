#pragma once
// The CPU reference for the synthetic view: textured triangles, perspective-correct, z-buffered.

#include <cstdint>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::render {

/// Where the rasteriser writes: RGB(A) colour and a depth buffer of 1/z_eye (0 = nothing drawn),
/// both width x height, tightly packed, row 0 at the top. rgba == nullptr: depth only.
struct RasterTarget {
  uint8_t* rgba = nullptr;
  float* inv_depth = nullptr;
  int width = 0;
  int height = 0;
};

/// Rasterises every mesh of a scene for one eye into rows [row_begin, row_end) of a target.
///
/// Conventions (the GL compositor reproduces them): a pixel is covered when its centre is inside
/// the projected triangle or on a top or left edge (D3D/GL top-left rule, with y down); triangles
/// are clipped in eye space against the near plane z = near_m and the far plane z = far_m;
/// attributes are interpolated perspective-correctly at the pixel centre; a fragment replaces
/// the stored one only if strictly closer (GL_LESS); textures are sampled bilinearly, clamped.
/// Row bands are independent, so splitting the rows over threads gives the same picture.
class MeshRasterizer {
 public:
  /// Transforms the scene's vertices into the eye frame (once per frame, before any band).
  /// Allocates only when the scene grows beyond what it held before.
  void prepare(const SyntheticScene& scene, const core::Pinhole& eye, const core::Pose& T_world_eye,
               double near_m, double far_m);

  /// Draws into rows [row_begin, row_end); the caller has cleared those rows' depth to 0.
  void draw_rows(const SyntheticScene& scene, const RasterTarget& target, int row_begin,
                 int row_end) const;

 private:
  struct EyeVertex {
    double x, y, z;  ///< eye frame, metres
    double s, t;     ///< texture coordinates
  };
  void draw_triangle(const TexturedMesh& mesh, const EyeVertex* v, const RasterTarget& target,
                     int row_begin, int row_end) const;

  core::Pinhole eye_;
  double near_m_ = 0.05;
  double far_m_ = 100.0;
  std::vector<EyeVertex> vertices_;     ///< all meshes' vertices in the eye frame, concatenated
  std::vector<std::size_t> mesh_base_;  ///< index of each mesh's first vertex in vertices_
  std::vector<uint8_t> mesh_ok_;        ///< meshes failing TexturedMesh::valid are skipped
};

}  // namespace hd::render
