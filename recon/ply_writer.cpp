#include "recon/ply_writer.h"

#include <bit>
#include <cstring>
#include <sstream>

namespace hd::recon {

static_assert(std::endian::native == std::endian::little,
              "ply_bytes writes the host's floats as binary_little_endian");

namespace {
template <typename T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}
}  // namespace

std::string ply_bytes(const DepthMesh& mesh, const std::string& comment) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n"
    << "comment hybrid display: workspace frame (x right, y down, z forward), metres\n";
  if (!comment.empty()) h << "comment " << comment << "\n";
  h << "element vertex " << mesh.positions_m.size() << "\n"
    << "property float x\nproperty float y\nproperty float z\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "element face " << mesh.triangles.size() << "\n"
    << "property list uchar int vertex_indices\nend_header\n";
  std::string out = h.str();
  out.reserve(out.size() + mesh.positions_m.size() * 15 + mesh.triangles.size() * 13);
  const bool colour = mesh.colours_rgb.size() == mesh.positions_m.size();
  for (std::size_t i = 0; i < mesh.positions_m.size(); ++i) {
    const Eigen::Vector3f& p = mesh.positions_m[i];
    put(out, p.x());
    put(out, p.y());
    put(out, p.z());
    const std::array<uint8_t, 3> c = colour ? mesh.colours_rgb[i] : std::array<uint8_t, 3>{};
    for (uint8_t v : c) put(out, v);
  }
  for (const auto& t : mesh.triangles) {
    put(out, uint8_t{3});
    for (uint32_t v : t) put(out, static_cast<int32_t>(v));
  }
  return out;
}

}  // namespace hd::recon
