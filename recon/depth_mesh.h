#pragma once
// The reconstructed surface of one stereo pair: a triangle mesh over the left image's pixel grid
// in workspace coordinates, broken where the depth jumps.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "recon/rectification.h"

namespace hd::recon {

/// Vertices in world metres; texcoords address the LEFT camera's original (unrectified) image in
/// render::TexturedMesh's convention (s = 0 at its left edge, 1 at its right edge, t = 0 at the
/// top row; texel i centred at (i + 0.5) / width); colours are the rectified left image's RGB.
struct DepthMesh {
  std::vector<Eigen::Vector3f> positions_m;
  std::vector<Eigen::Vector2f> texcoords;
  std::vector<std::array<uint8_t, 3>> colours_rgb;
  std::vector<std::array<uint32_t, 3>> triangles;

  void clear() {
    positions_m.clear();
    texcoords.clear();
    colours_rgb.clear();
    triangles.clear();
  }
};

struct DepthMeshConfig {
  /// Grid spacing in rectified pixels: a vertex every stride_px pixels in x and y.
  int stride_px = 2;
  /// A triangle is kept only if its corners' disparities differ by at most this much per pixel
  /// of grid spacing. 0.5 px/px keeps surfaces up to about 80 degrees from facing the camera at
  /// the station's distances and breaks the mesh at object outlines (docs/reconstruction.md).
  double max_disparity_slope = 0.5;

  void check() const;  ///< throws std::invalid_argument naming the field
};

/// Builds `out` (cleared first; its capacity is reused) from a filtered disparity map (CV_32F,
/// rectified left pixels, NaN = unknown) of `rect`'s pair. `left_rect_bgr` (CV_8UC3 of the same
/// size, or empty) gives the vertex colours (grey 128 without it).
void build_depth_mesh(const cv::Mat& disparity, const Rectification& rect,
                      const cv::Mat& left_rect_bgr, const DepthMeshConfig& config, DepthMesh& out);

}  // namespace hd::recon
