#include "sim/primitive_meshes.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "core/config/config_error.h"

namespace hd::sim {

namespace {

constexpr int kTexelsPerCell = 8;
constexpr int kMaxTexture = 1024;

render::ImageRgba8 checker(const SceneTexture& t, double width_m, double height_m, double shade) {
  const int cx = std::clamp(static_cast<int>(std::lround(width_m / t.cell_m)), 1,
                            kMaxTexture / kTexelsPerCell);
  const int cy = std::clamp(static_cast<int>(std::lround(height_m / t.cell_m)), 1,
                            kMaxTexture / kTexelsPerCell);
  render::ImageRgba8 img;
  img.allocate(cx * kTexelsPerCell, cy * kTexelsPerCell);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const auto& c = ((x / kTexelsPerCell + y / kTexelsPerCell) & 1) ? t.color1 : t.color0;
      uint8_t* p = img.pixel(x, y);
      for (int i = 0; i < 3; ++i)
        p[i] = static_cast<uint8_t>(std::lround(c[static_cast<std::size_t>(i)] * shade));
      p[3] = 255;
    }
  }
  return img;
}

render::ImageRgba8 image_texture(const SceneTexture& t, double shade,
                                 const std::string& scene_file) {
  const cv::Mat bgr = cv::imread(t.image_path, cv::IMREAD_COLOR);
  if (bgr.empty()) {
    throw config::ConfigError(scene_file, 0, 0, "texture.file",
                              "cannot read image '" + t.image_path + "'");
  }
  cv::Mat rgba;
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  render::ImageRgba8 img;
  img.allocate(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) {
    const uint8_t* src = rgba.ptr<uint8_t>(y);
    uint8_t* dst = img.row(y);
    for (int x = 0; x < 4 * rgba.cols; ++x) {
      dst[x] = (x % 4 == 3) ? 255 : static_cast<uint8_t>(std::lround(src[x] * shade));
    }
  }
  return img;
}

/// A rectangle with corners a (top-left of the texture), b (top-right), c, d.
render::TexturedMesh face(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c, const Eigen::Vector3d& d, const SceneTexture& t,
                          double shade, const std::string& scene_file) {
  render::TexturedMesh m;
  m.positions_m = {a.cast<float>(), b.cast<float>(), c.cast<float>(), d.cast<float>()};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture = t.kind == SceneTexture::Kind::kImage
                  ? image_texture(t, shade, scene_file)
                  : checker(t, (b - a).norm(), (d - a).norm(), shade);
  return m;
}

}  // namespace

std::vector<render::TexturedMesh> primitive_meshes(const ScenePrimitive& p,
                                                   const std::string& scene_file) {
  const Eigen::Matrix3d R = rotation_from_ypr_deg(p.ypr_deg);
  auto at = [&](double x, double y, double z) -> Eigen::Vector3d {
    return R * Eigen::Vector3d(x, y, z) + p.center_m;
  };
  const double hx = p.size_m.x() / 2, hy = p.size_m.y() / 2, hz = p.size_m.z() / 2;
  std::vector<render::TexturedMesh> out;
  if (p.shape == ScenePrimitive::Shape::kQuad) {
    out.push_back(face(at(-hx, -hy, 0), at(hx, -hy, 0), at(hx, hy, 0), at(-hx, hy, 0), p.texture,
                       1.0, scene_file));
    return out;
  }
  // y is down: the top face is at -hy.
  out.push_back(face(at(-hx, -hy, hz), at(hx, -hy, hz), at(hx, -hy, -hz), at(-hx, -hy, -hz),
                     p.texture, 1.0, scene_file));  // top
  out.push_back(face(at(-hx, -hy, -hz), at(hx, -hy, -hz), at(hx, hy, -hz), at(-hx, hy, -hz),
                     p.texture, 0.85, scene_file));  // front (-z)
  out.push_back(face(at(hx, -hy, hz), at(-hx, -hy, hz), at(-hx, hy, hz), at(hx, hy, hz), p.texture,
                     0.8, scene_file));  // back (+z)
  out.push_back(face(at(-hx, -hy, hz), at(-hx, -hy, -hz), at(-hx, hy, -hz), at(-hx, hy, hz),
                     p.texture, 0.7, scene_file));  // left (-x)
  out.push_back(face(at(hx, -hy, -hz), at(hx, -hy, hz), at(hx, hy, hz), at(hx, hy, -hz), p.texture,
                     0.75, scene_file));  // right (+x)
  out.push_back(face(at(-hx, hy, -hz), at(hx, hy, -hz), at(hx, hy, hz), at(-hx, hy, hz), p.texture,
                     0.6, scene_file));  // bottom
  return out;
}

}  // namespace hd::sim
