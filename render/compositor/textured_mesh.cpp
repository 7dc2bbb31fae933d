#include "render/compositor/textured_mesh.h"

#include <cmath>
#include <cstddef>

namespace hd::render {

bool TexturedMesh::valid() const {
  if (uvs.size() != positions_m.size() || texture.empty()) return false;
  if (texture.stride_bytes < 4 * texture.width || texture.stride_bytes % 4 != 0) return false;
  if (texture.data.size() <
      static_cast<std::size_t>(texture.stride_bytes) * static_cast<std::size_t>(texture.height)) {
    return false;
  }
  for (const auto& p : positions_m) {
    if (!p.allFinite()) return false;
  }
  for (const auto& uv : uvs) {
    if (!uv.allFinite()) return false;
  }
  for (const auto& tri : triangles) {
    for (uint32_t i : tri) {
      if (i >= positions_m.size()) return false;
    }
  }
  return true;
}

}  // namespace hd::render
