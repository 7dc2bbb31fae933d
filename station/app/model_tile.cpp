#include "station/app/model_tile.h"

#include <opencv2/imgproc.hpp>
#include <vector>

#include "render/compositor/mesh_rasterizer.h"

namespace hd::station {

cv::Mat render_model_tile(const ModelSnapshot& snapshot, const core::Pinhole& eye,
                          const core::Pose& T_world_eye) {
  render::SyntheticScene scene = snapshot.scene;
  for (std::size_t m = snapshot.prior_meshes; m < scene.meshes.size(); ++m) {
    std::vector<uint8_t>& px = scene.meshes[m].texture.data;
    for (std::size_t i = 0; i + 3 < px.size(); i += 4) {
      px[i] = static_cast<uint8_t>((px[i] + 255) / 2);
      px[i + 1] = static_cast<uint8_t>(px[i + 1] / 2);
      px[i + 2] = static_cast<uint8_t>((px[i + 2] + 255) / 2);
    }
  }
  const int w = eye.width, h = eye.height;
  cv::Mat rgba(
      h, w, CV_8UC4,
      cv::Scalar(scene.background_rgb[0], scene.background_rgb[1], scene.background_rgb[2], 255));
  std::vector<float> inv(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0f);
  render::MeshRasterizer raster;
  raster.prepare(scene, eye, T_world_eye, 0.05, 100.0);
  raster.draw_rows(scene, render::RasterTarget{rgba.data, inv.data(), w, h}, 0, h);
  cv::Mat bgr;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  return bgr;
}

std::string model_tile_label(const ModelSnapshot& snapshot) {
  std::size_t vertices = 0;
  for (std::size_t m = snapshot.prior_meshes; m < snapshot.scene.meshes.size(); ++m)
    if (!snapshot.scene.meshes[m].triangles.empty())  // an empty one is a placeholder
      vertices += snapshot.scene.meshes[m].positions_m.size();
  return "model #" + std::to_string(snapshot.update) + ", reconstructed: magenta (" +
         std::to_string(vertices) + " v)";
}

}  // namespace hd::station
