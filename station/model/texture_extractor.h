#pragma once
// Projective texturing: the model's textures taken from camera frames onto the known geometry.

#include <cstdint>
#include <span>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/frame.h"
#include "render/compositor/mesh_rasterizer.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::station {

/// One camera frame to texture from: an undistorted RGBA8 frame matching the pinhole `p_c`
/// (what CameraPipeline publishes) taken from pose `T_world_cam`.
struct ExtractionView {
  const drivers::Frame* frame = nullptr;
  core::Pinhole p_c;
  core::Pose T_world_cam;
};

struct TextureExtractorParams {
  double near_m = 0.05;  ///< points closer to a camera than this are not seen by it
  double far_m = 100.0;  ///< the depth map's far plane
  /// A texel is unoccluded when its depth z from the camera satisfies
  /// z <= z_map * (1 + depth_bias_rel) + depth_bias_m at each of its bilinear footprint pixels
  /// (z_map: the nearest surface there, from a MeshRasterizer depth map of the same scene).
  double depth_bias_rel = 0.01;
  double depth_bias_m = 0.002;
  /// Texels seen at a grazing angle (cos between the surface normal and the ray to the camera
  /// below this) are not taken: their colour would be smeared along the surface.
  double min_cos = 0.1;
};

/// What one extract() did (for tests, the docs and the station's log).
struct ExtractionStats {
  uint64_t texels_mapped = 0;   ///< texels that lie on (or within a texel of) a UV triangle
  uint64_t texels_updated = 0;  ///< texels that took a colour from some frame
  uint64_t views_used = 0;      ///< views whose frame matched their pinhole
  uint64_t views_rejected = 0;  ///< null frame, wrong size/format, invalid pinhole or pose
};

/// For every texel of every mesh texture, its point on the mesh is found once (prepare(): the
/// texel centre ((i+0.5)/w, (j+0.5)/h) inside a UV triangle gives that triangle and barycentric
/// coordinates; texels just outside every UV triangle, up to one texel away, take the nearest
/// covered neighbour's triangle, extrapolated on its plane, so bilinear sampling at UV seams
/// reads fresh colours too). extract() then, with the scene's current vertex positions (moving
/// objects may have moved), projects each texel's world point into every view; the texel is seen
/// when the point is in front of the camera, its 2x2 bilinear footprint lies inside the image,
/// the surface faces the camera at least min_cos, and no other surface is closer at any footprint
/// pixel. A seen texel takes the frame's bilinear colour (alpha 255); when several views see it,
/// the one that sees it most frontally (largest cos) wins, ties to the earlier view. Unseen
/// texels keep their colour.
///
/// After prepare(), extract() allocates nothing as long as the scene keeps its mesh count,
/// triangle lists and texture sizes, and views are no larger than the largest seen before
/// (buffers grow once).
class TextureExtractor {
 public:
  explicit TextureExtractor(TextureExtractorParams params = {}) : params_(params) {}

  /// Maps texels to mesh points for `scene` (its UVs and texture sizes; positions may change
  /// later). Invalid meshes (TexturedMesh::valid() false) are skipped.
  void prepare(const render::SyntheticScene& scene);

  /// Textures `scene` (the same meshes and textures prepare() saw) from `views`. Returns false
  /// without touching anything when the scene's shape no longer matches prepare(). Meshes after
  /// the ones prepare() saw (the model updater's reconstructed meshes) take part in the
  /// occlusion test only: their texture is their own camera's frame.
  bool extract(render::SyntheticScene& scene, std::span<const ExtractionView> views);

  const ExtractionStats& last_stats() const { return stats_; }
  const TextureExtractorParams& params() const { return params_; }

 private:
  struct TexelPoint {
    uint32_t texel = 0;     ///< j * width + i
    uint32_t triangle = 0;  ///< index into the mesh's triangles
    float b1 = 0, b2 = 0;   ///< barycentric weights of vertices 1 and 2 (vertex 0: 1 - b1 - b2)
  };
  struct MeshMap {
    bool ok = false;
    int tex_width = 0, tex_height = 0;
    std::size_t triangle_count = 0;
    std::vector<TexelPoint> points;
  };
  bool matches(const render::SyntheticScene& scene) const;
  void extract_view(render::SyntheticScene& scene, const ExtractionView& view);

  TextureExtractorParams params_;
  std::vector<MeshMap> maps_;
  std::vector<std::vector<float>> best_cos_;  ///< per mesh, per mapped point: winning cos so far
  std::vector<Eigen::Vector3d> normals_;      ///< per triangle of the mesh being processed
  render::MeshRasterizer rasterizer_;
  std::vector<uint8_t> depth_rgba_;  ///< colour the rasterizer writes (unused)
  std::vector<float> inv_depth_;
  ExtractionStats stats_;
};

}  // namespace hd::station
