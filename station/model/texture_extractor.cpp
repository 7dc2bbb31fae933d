#include "station/model/texture_extractor.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/opencv_pixels.h"
#include "station/video/frame_copy.h"

namespace hd::station {
namespace {

// Barycentric weights (b1, b2) of point p for triangle (a, b, c) in texel space; extrapolates
// outside. Returns false for a degenerate triangle.
bool barycentric(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                 const Eigen::Vector2d& p, double& b1, double& b2) {
  const Eigen::Vector2d e1 = b - a, e2 = c - a, d = p - a;
  const double det = e1.x() * e2.y() - e1.y() * e2.x();
  if (!(std::abs(det) > 1e-12)) return false;
  b1 = (d.x() * e2.y() - d.y() * e2.x()) / det;
  b2 = (e1.x() * d.y() - e1.y() * d.x()) / det;
  return true;
}

}  // namespace

void TextureExtractor::prepare(const render::SyntheticScene& scene) {
  maps_.assign(scene.meshes.size(), MeshMap{});
  best_cos_.assign(scene.meshes.size(), {});
  std::vector<int32_t> owner;
  std::vector<float> bary;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const render::TexturedMesh& mesh = scene.meshes[m];
    MeshMap& map = maps_[m];
    map.tex_width = mesh.texture.width;
    map.tex_height = mesh.texture.height;
    map.triangle_count = mesh.triangles.size();
    map.ok = mesh.valid();
    if (!map.ok) continue;
    const int w = mesh.texture.width, h = mesh.texture.height;
    owner.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), -1);
    bary.assign(owner.size() * 2, 0.0f);
    auto texel_uv = [&](uint32_t vertex) {
      return Eigen::Vector2d(mesh.uvs[vertex].x() * w, mesh.uvs[vertex].y() * h);
    };
    // Texel centres inside a UV triangle (edges included; the first triangle wins).
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector2d a = texel_uv(tri[0]), b = texel_uv(tri[1]), c = texel_uv(tri[2]);
      const double min_x = std::min({a.x(), b.x(), c.x()}), max_x = std::max({a.x(), b.x(), c.x()});
      const double min_y = std::min({a.y(), b.y(), c.y()}), max_y = std::max({a.y(), b.y(), c.y()});
      const int i0 = std::max(0, static_cast<int>(std::floor(min_x - 0.5)));
      const int i1 = std::min(w - 1, static_cast<int>(std::ceil(max_x - 0.5)));
      const int j0 = std::max(0, static_cast<int>(std::floor(min_y - 0.5)));
      const int j1 = std::min(h - 1, static_cast<int>(std::ceil(max_y - 0.5)));
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const std::size_t k = static_cast<std::size_t>(j) * static_cast<std::size_t>(w) +
                                static_cast<std::size_t>(i);
          if (owner[k] >= 0) continue;
          double b1 = 0, b2 = 0;
          if (!barycentric(a, b, c, {i + 0.5, j + 0.5}, b1, b2)) break;
          constexpr double kEdge = -1e-9;
          if (b1 < kEdge || b2 < kEdge || 1.0 - b1 - b2 < kEdge) continue;
          owner[k] = static_cast<int32_t>(t);
          bary[2 * k] = static_cast<float>(b1);
          bary[2 * k + 1] = static_cast<float>(b2);
        }
      }
    }
    // One texel of dilation: bilinear sampling at a UV edge also reads the texel just outside
    // it, so that texel takes its covered neighbour's triangle, extrapolated on its plane.
    std::vector<int32_t> grown = owner;
    for (int j = 0; j < h; ++j) {
      for (int i = 0; i < w; ++i) {
        const std::size_t k =
            static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
        if (owner[k] >= 0) continue;
        for (int dj = -1; dj <= 1 && grown[k] < 0; ++dj) {
          for (int di = -1; di <= 1; ++di) {
            const int ni = i + di, nj = j + dj;
            if (ni < 0 || nj < 0 || ni >= w || nj >= h) continue;
            const int32_t t = owner[static_cast<std::size_t>(nj) * static_cast<std::size_t>(w) +
                                    static_cast<std::size_t>(ni)];
            if (t < 0) continue;
            const auto& tri = mesh.triangles[static_cast<std::size_t>(t)];
            double b1 = 0, b2 = 0;
            if (!barycentric(texel_uv(tri[0]), texel_uv(tri[1]), texel_uv(tri[2]),
                             {i + 0.5, j + 0.5}, b1, b2))
              continue;
            grown[k] = t;
            bary[2 * k] = static_cast<float>(b1);
            bary[2 * k + 1] = static_cast<float>(b2);
            break;
          }
        }
      }
    }
    for (std::size_t k = 0; k < grown.size(); ++k) {
      if (grown[k] < 0) continue;
      map.points.push_back({static_cast<uint32_t>(k), static_cast<uint32_t>(grown[k]), bary[2 * k],
                            bary[2 * k + 1]});
    }
    best_cos_[m].assign(map.points.size(), 0.0f);
  }
}

bool TextureExtractor::matches(const render::SyntheticScene& scene) const {
  // Meshes after those prepare() saw (the reconstructed ones) occlude but are not textured.
  if (scene.meshes.size() < maps_.size()) return false;
  for (std::size_t m = 0; m < maps_.size(); ++m) {
    const render::TexturedMesh& mesh = scene.meshes[m];
    const MeshMap& map = maps_[m];
    if (mesh.texture.width != map.tex_width || mesh.texture.height != map.tex_height ||
        mesh.triangles.size() != map.triangle_count)
      return false;
    if (map.ok && !mesh.valid()) return false;
  }
  return true;
}

bool TextureExtractor::extract(render::SyntheticScene& scene,
                               std::span<const ExtractionView> views) {
  stats_ = ExtractionStats{};
  if (!matches(scene)) return false;
  for (std::size_t m = 0; m < maps_.size(); ++m) {
    std::fill(best_cos_[m].begin(), best_cos_[m].end(), 0.0f);
    stats_.texels_mapped += maps_[m].points.size();
  }
  for (const ExtractionView& view : views) {
    if (view.frame == nullptr || !view.p_c.valid() || !view.T_world_cam.valid() ||
        !is_rgba_frame(*view.frame, view.p_c.width, view.p_c.height)) {
      ++stats_.views_rejected;
      continue;
    }
    ++stats_.views_used;
    extract_view(scene, view);
  }
  return true;
}

void TextureExtractor::extract_view(render::SyntheticScene& scene, const ExtractionView& view) {
  const core::Pinhole& k = view.p_c;
  const int w = k.width, h = k.height;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (inv_depth_.size() < pixels) {
    inv_depth_.resize(pixels);
    depth_rgba_.resize(pixels * 4);
  }
  // Depth of the nearest surface at every pixel centre, from the same geometry.
  std::fill(inv_depth_.begin(), inv_depth_.begin() + static_cast<std::ptrdiff_t>(pixels), 0.0f);
  rasterizer_.prepare(scene, k, view.T_world_cam, params_.near_m, params_.far_m);
  rasterizer_.draw_rows(scene, render::RasterTarget{depth_rgba_.data(), inv_depth_.data(), w, h}, 0,
                        h);

  const Eigen::Matrix3d Rt = view.T_world_cam.R.transpose();
  const Eigen::Vector3d centre = view.T_world_cam.t;
  const drivers::Frame& frame = *view.frame;
  const uint8_t* img = frame.data.data();
  const std::ptrdiff_t stride = frame.stride_bytes;
  const double rel = 1.0 + params_.depth_bias_rel, abs_m = params_.depth_bias_m;

  for (std::size_t m = 0; m < maps_.size(); ++m) {
    const MeshMap& map = maps_[m];
    if (!map.ok) continue;
    render::TexturedMesh& mesh = scene.meshes[m];
    const std::size_t tris = mesh.triangles.size();
    if (normals_.size() < tris) normals_.resize(tris);
    for (std::size_t t = 0; t < tris; ++t) {
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3d p0 = mesh.positions_m[tri[0]].cast<double>();
      const Eigen::Vector3d n = (mesh.positions_m[tri[1]].cast<double>() - p0)
                                    .cross(mesh.positions_m[tri[2]].cast<double>() - p0);
      const double len = n.norm();
      normals_[t] = len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
    }
    float* best = best_cos_[m].data();
    const int tw = mesh.texture.width;
    for (std::size_t q = 0; q < map.points.size(); ++q) {
      const TexelPoint& tp = map.points[q];
      const auto& tri = mesh.triangles[tp.triangle];
      const Eigen::Vector3d p0 = mesh.positions_m[tri[0]].cast<double>();
      const Eigen::Vector3d X = p0 + tp.b1 * (mesh.positions_m[tri[1]].cast<double>() - p0) +
                                tp.b2 * (mesh.positions_m[tri[2]].cast<double>() - p0);
      const Eigen::Vector3d to_cam = centre - X;
      const double dist = to_cam.norm();
      if (!(dist > 0)) continue;
      // Compared as stored (float), so a tie between views really is a tie.
      const float cos = static_cast<float>(std::abs(normals_[tp.triangle].dot(to_cam)) / dist);
      if (cos < params_.min_cos || cos <= best[q]) continue;
      const Eigen::Vector3d Xc = Rt * (X - centre);
      const double z = Xc.z();
      if (!(z >= params_.near_m) || z > params_.far_m) continue;
      // Bilinear footprint in OpenCV's numbering (pixel centres at integers): the depth buffer's
      // pixel (x0, y0) has its centre there.
      const Eigen::Vector2d f_px = core::to_opencv_px(k.project(Xc));
      const double fx = f_px.x(), fy = f_px.y();
      if (!(fx >= 0.0 && fy >= 0.0 && fx < w - 1 && fy < h - 1)) continue;
      const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
      const double ax = fx - x0, ay = fy - y0;
      const std::size_t d0 =
          static_cast<std::size_t>(y0) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x0);
      const float inv[4] = {inv_depth_[d0], inv_depth_[d0 + 1], inv_depth_[d0 + w],
                            inv_depth_[d0 + w + 1]};
      bool seen = true;
      for (float id : inv) {
        // inv 0: nothing drawn at that pixel centre (just past a silhouette), nothing closer.
        if (id > 0.0f && z > rel / static_cast<double>(id) + abs_m) {
          seen = false;
          break;
        }
      }
      if (!seen) continue;
      const uint8_t* r0 = img + y0 * stride + 4 * x0;
      const uint8_t* r1 = r0 + stride;
      uint8_t* texel = mesh.texture.pixel(static_cast<int>(tp.texel % static_cast<uint32_t>(tw)),
                                          static_cast<int>(tp.texel / static_cast<uint32_t>(tw)));
      for (int c = 0; c < 3; ++c) {
        const double top = r0[c] + ax * (r0[4 + c] - r0[c]);
        const double bottom = r1[c] + ax * (r1[4 + c] - r1[c]);
        texel[c] = static_cast<uint8_t>(std::lround(top + ay * (bottom - top)));
      }
      texel[3] = 255;
      if (best[q] == 0.0f) ++stats_.texels_updated;
      best[q] = cos;
    }
  }
}

}  // namespace hd::station
