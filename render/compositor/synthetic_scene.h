#pragma once
// The synthetic model of the remote workspace, as the compositors draw it.

#include <array>
#include <cstdint>
#include <vector>

#include "render/compositor/textured_mesh.h"

namespace hd::render {

/// Meshes drawn depth-tested over a uniform background.
///
/// `revision` tells a GPU compositor when to re-upload: whoever changes a mesh or texture
/// increments it (a model/texture update); the same pointer with the same revision is not
/// re-uploaded.
struct SyntheticScene {
  std::vector<TexturedMesh> meshes;
  std::array<uint8_t, 3> background_rgb{40, 40, 48};  ///< where no mesh and no video is seen
  uint64_t revision = 0;
};

}  // namespace hd::render
