#include "render/compositor/demo_scene.h"

#include <algorithm>
#include <cmath>

#include "render/compositor/cpu_compositor.h"

namespace hd::render {

namespace {

TexturedMesh quad(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                  const Eigen::Vector3f& d, ImageRgba8 texture) {
  TexturedMesh m;
  m.positions_m = {a, b, c, d};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture = std::move(texture);
  return m;
}

ImageRgba8 checker_texture(int n, int cells, const uint8_t* c0, const uint8_t* c1) {
  ImageRgba8 t;
  t.allocate(n, n);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const uint8_t* c = (((x * cells / n) + (y * cells / n)) & 1) ? c1 : c0;
      uint8_t* p = t.pixel(x, y);
      p[0] = c[0];
      p[1] = c[1];
      p[2] = c[2];
      p[3] = 255;
    }
  }
  return t;
}

ImageRgba8 gradient_texture(int w, int h) {
  ImageRgba8 t;
  t.allocate(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = t.pixel(x, y);
      p[0] = static_cast<uint8_t>(60 + 150 * x / std::max(1, w - 1));
      p[1] = static_cast<uint8_t>(80 + 100 * y / std::max(1, h - 1));
      p[2] = 160;
      p[3] = 255;
    }
  }
  return t;
}

}  // namespace

SyntheticScene make_demo_scene() {
  SyntheticScene s;
  s.background_rgb = {30, 32, 40};
  const uint8_t wood0[3] = {170, 130, 90}, wood1[3] = {120, 85, 55};
  s.meshes.push_back(quad({-1.0f, 0.4f, 0.2f}, {1.0f, 0.4f, 0.2f}, {1.0f, 0.4f, 2.2f},
                          {-1.0f, 0.4f, 2.2f}, checker_texture(64, 8, wood0, wood1)));
  s.meshes.push_back(quad({-1.2f, -0.9f, 2.2f}, {1.2f, -0.9f, 2.2f}, {1.2f, 0.4f, 2.2f},
                          {-1.2f, 0.4f, 2.2f}, gradient_texture(64, 32)));
  // A box 0.3 m wide, centred at x = 0.15, z = 1.3, standing on the table (y = 0.4 up to 0.1).
  const float x0 = 0.0f, x1 = 0.3f, y0 = 0.1f, y1 = 0.4f, z0 = 1.15f, z1 = 1.45f;
  const uint8_t red0[3] = {200, 60, 50}, red1[3] = {150, 40, 35};
  const uint8_t blue0[3] = {60, 90, 200}, blue1[3] = {40, 60, 150};
  s.meshes.push_back(quad({x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0},
                          checker_texture(16, 2, red0, red1)));  // front
  s.meshes.push_back(quad({x0, y0, z1}, {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1},
                          checker_texture(16, 2, blue0, blue1)));  // left
  s.meshes.push_back(quad({x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0},
                          checker_texture(16, 2, blue0, blue1)));  // right
  s.meshes.push_back(quad({x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0}, {x0, y0, z0},
                          checker_texture(16, 2, red1, red0)));  // top
  s.revision = 1;
  return s;
}

void render_demo_frame(const SyntheticScene& scene, const core::Pinhole& camera,
                       const core::Pose& T_world_camera, int tint, drivers::Frame& frame) {
  if (frame.width != camera.width || frame.height != camera.height ||
      frame.format != drivers::PixelFormat::kRgba8) {
    frame.allocate_rgba(camera.width, camera.height);
  }
  ImageRgba8 img;
  img.allocate(camera.width, camera.height);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = camera;
  req.T_world_eye = T_world_camera;
  req.marking.style = core::MarkingStyle::kNone;
  req.viewport = {0, 0, camera.width, camera.height};
  CpuCompositor cpu;
  cpu.draw(req, img);
  for (int y = 0; y < camera.height; ++y) {
    uint8_t* dst = frame.data.data() + static_cast<long>(y) * frame.stride_bytes;
    for (int x = 0; x < camera.width; ++x) {
      const uint8_t* p = img.pixel(x, y);
      // Soft diagonal stripes: detail only the video has, smooth enough to sample well.
      const double stripe = 12.0 * std::sin((x + y) * 0.25);
      for (int c = 0; c < 3; ++c) {
        const double v = p[c] + tint * (c == 1 ? 1 : -1) + stripe;
        dst[4 * x + c] = static_cast<uint8_t>(std::clamp(v, 0.0, 255.0));
      }
      dst[4 * x + 3] = 255;
    }
  }
}

}  // namespace hd::render
