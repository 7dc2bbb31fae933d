#pragma once
// Textured meshes of a scene primitive (box or quad), as the compositors draw them.

#include <vector>

#include "render/compositor/textured_mesh.h"
#include "sim/scene/scene.h"

namespace hd::sim {

/// The meshes of `p` in its parent frame (the world for static geometry, the object's origin for
/// a moving object): a quad is one mesh, a box six (one per face, each with its own texture so a
/// checker keeps its cell size; side faces darker than the top so edges are visible). Throws
/// config::ConfigError naming the file when an image texture cannot be read.
std::vector<render::TexturedMesh> primitive_meshes(const ScenePrimitive& p,
                                                   const std::string& scene_file);

}  // namespace hd::sim
