#pragma once
// A DepthMesh as a PLY file (binary little-endian, the format MeshLab and Open3D read).

#include <string>

#include "recon/depth_mesh.h"

namespace hd::recon {

/// The bytes of a PLY file: vertices as float x y z (metres, workspace frame) with uchar red
/// green blue, faces as a uchar-counted list of int vertex indices, and a comment naming the
/// frame. `comment` lines (no newlines) are added to the header.
std::string ply_bytes(const DepthMesh& mesh, const std::string& comment = "");

}  // namespace hd::recon
