#pragma once
// One piece of the synthetic model: triangles in the workspace with one texture.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "render/compositor/image_rgba8.h"

namespace hd::render {

/// A triangle mesh in world metres with one RGBA texture.
///
/// Texture coordinates: s runs from 0 at the left edge of `texture` to 1 at its right edge, t from
/// 0 at its TOP row (row 0 of `texture`) to 1 at its bottom row. Texel (i, j) has its centre at
/// ((i+0.5)/w, (j+0.5)/h). Sampling is bilinear between texel centres, clamped to the edge
/// texels (no wrap), with no sRGB conversion; both compositors follow this exactly.
/// Triangles may face either way (no back-face culling): a model seen from behind still occludes.
struct TexturedMesh {
  std::vector<Eigen::Vector3f> positions_m;        ///< vertex positions in the world frame, metres
  std::vector<Eigen::Vector2f> uvs;                ///< (s, t) per vertex, same count as positions
  std::vector<std::array<uint32_t, 3>> triangles;  ///< indices into positions_m / uvs
  ImageRgba8 texture;                              ///< alpha is ignored (the model is opaque)

  /// Every index in range, uvs match positions, texture non-empty with a whole-pixel stride
  /// (a multiple of 4 bytes, as GL_UNPACK_ROW_LENGTH needs), all values finite. Both compositors
  /// skip an invalid mesh.
  bool valid() const;
};

}  // namespace hd::render
