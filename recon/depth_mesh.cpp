#include "recon/depth_mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "recon/disparity_points.h"

namespace hd::recon {

void DepthMeshConfig::check() const {
  if (stride_px < 1 || stride_px > 64)
    throw std::invalid_argument("mesh.stride_px: must be in 1..64");
  if (!(max_disparity_slope > 0))
    throw std::invalid_argument("mesh.max_disparity_slope: must be > 0");
}

void build_depth_mesh(const cv::Mat& disparity, const Rectification& rect,
                      const cv::Mat& left_rect_bgr, const DepthMeshConfig& config, DepthMesh& out) {
  config.check();
  if (disparity.type() != CV_32FC1 || disparity.size() != rect.size())
    throw std::invalid_argument("build_depth_mesh: expected a CV_32F map of the rectified size");
  const bool colour = !left_rect_bgr.empty();
  if (colour && (left_rect_bgr.type() != CV_8UC3 || left_rect_bgr.size() != rect.size()))
    throw std::invalid_argument("build_depth_mesh: colour image must be CV_8UC3, rectified size");
  out.clear();
  const DisparityToWorld to_world(rect);
  const int s = config.stride_px;
  const int gw = (disparity.cols - 1) / s + 1, gh = (disparity.rows - 1) / s + 1;
  const float max_step = static_cast<float>(config.max_disparity_slope * s);
  const float tex_w = static_cast<float>(rect.rig().left.width);
  const float tex_h = static_cast<float>(rect.rig().left.height);
  constexpr uint32_t kNone = ~uint32_t{0};
  std::vector<uint32_t> index(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh), kNone);
  std::vector<float> grid_d(index.size(), 0.0f);

  for (int j = 0; j < gh; ++j) {
    const int y = j * s;
    const float* d = disparity.ptr<float>(y);
    const float* mx = rect.left_map_x().ptr<float>(y);
    const float* my = rect.left_map_y().ptr<float>(y);
    for (int i = 0; i < gw; ++i) {
      const int x = i * s;
      const auto X = to_world.point(x, y, d[x]);
      if (!X) continue;
      const std::size_t g = static_cast<std::size_t>(j) * gw + i;
      index[g] = static_cast<uint32_t>(out.positions_m.size());
      grid_d[g] = d[x];
      out.positions_m.push_back(X->cast<float>());
      out.texcoords.emplace_back((mx[x] + 0.5f) / tex_w, (my[x] + 0.5f) / tex_h);
      if (colour) {
        const cv::Vec3b c = left_rect_bgr.at<cv::Vec3b>(y, x);
        out.colours_rgb.push_back({c[2], c[1], c[0]});
      } else {
        out.colours_rgb.push_back({128, 128, 128});
      }
    }
  }

  auto add = [&](std::size_t a, std::size_t b, std::size_t c) {
    const float lo = std::min({grid_d[a], grid_d[b], grid_d[c]});
    const float hi = std::max({grid_d[a], grid_d[b], grid_d[c]});
    if (hi - lo <= max_step) out.triangles.push_back({index[a], index[b], index[c]});
  };
  for (int j = 0; j + 1 < gh; ++j) {
    for (int i = 0; i + 1 < gw; ++i) {
      const std::size_t a = static_cast<std::size_t>(j) * gw + i, b = a + 1;
      const std::size_t c = a + static_cast<std::size_t>(gw), e = c + 1;
      const bool ka = index[a] != kNone, kb = index[b] != kNone, kc = index[c] != kNone,
                 ke = index[e] != kNone;
      // Two triangles per full cell, one where a single corner is missing.
      if (ka && kb && kc && ke) {
        add(a, c, b);
        add(b, c, e);
      } else if (ka && kb && kc) {
        add(a, c, b);
      } else if (ka && kb && ke) {
        add(a, e, b);
      } else if (ka && kc && ke) {
        add(a, c, e);
      } else if (kb && kc && ke) {
        add(b, c, e);
      }
    }
  }
}

}  // namespace hd::recon
