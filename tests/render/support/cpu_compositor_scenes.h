#pragma once
// What the CPU compositor's tests (tests/render/compositor_cpu_*_test.cpp) draw: eye and camera
// pinholes, position-coded and uniform video frames, a video request with every mark off, and a
// textured quad facing the eye.

#include <Eigen/Geometry>
#include <cstdint>

#include "render/compositor/cpu_compositor.h"
#include "render/compositor/look_pose.h"

namespace hd::render::test {

using ::hd::core::MarkingStyle;
using ::hd::core::Pinhole;
using ::hd::core::Pose;
using ::hd::core::TransitionMode;
using ::hd::core::Variant;
using ::hd::drivers::Frame;
using ::hd::render::CompositeRequest;
using ::hd::render::CpuCompositor;
using ::hd::render::ImageRgba8;
using ::hd::render::look_pose;
using ::hd::render::SyntheticScene;
using ::hd::render::TexturedMesh;

inline Pinhole pinhole(double f, int w, int h) {
  return Pinhole::centred(f, w, h);
}

// The model alone as the eye sees it (no video, no marking), at the eye's size.
inline ImageRgba8 draw_model(const SyntheticScene& scene, const Pinhole& eye, double near_m = 0.05,
                             const Pose& T_world_eye = Pose::identity()) {
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(eye.width, eye.height);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.T_world_eye = T_world_eye;
  req.near_m = near_m;
  req.marking.style = MarkingStyle::kNone;
  req.viewport = {0, 0, eye.width, eye.height};
  comp.draw(req, out);
  return out;
}

// A frame whose every pixel has a distinct, position-coded colour.
inline Frame coded_frame(int w, int h) {
  Frame f;
  f.allocate_rgba(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      uint8_t* p = f.data.data() + y * f.stride_bytes + 4 * x;
      p[0] = static_cast<uint8_t>(x * 7 + y);
      p[1] = static_cast<uint8_t>(y * 5 + x * 3);
      p[2] = static_cast<uint8_t>(x ^ y);
      p[3] = 255;
    }
  }
  return f;
}

inline Frame uniform_frame(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  Frame f;
  f.allocate_rgba(w, h);
  for (std::size_t i = 0; i < f.data.size(); i += 4) {
    f.data[i] = r;
    f.data[i + 1] = g;
    f.data[i + 2] = b;
    f.data[i + 3] = 255;
  }
  return f;
}

inline CompositeRequest video_request(const Pinhole& eye, const Frame* frame, const Pinhole& real) {
  CompositeRequest r;
  r.eye = eye;
  r.video = frame;
  r.real = real;
  r.d_m = 2.0;
  r.has_region = true;
  r.region = {0, 0, static_cast<double>(real.width), static_cast<double>(real.height)};
  r.transition = {Variant::kVideo, 1.0, 0.0};
  r.mode = TransitionMode::kGlobalBlend;
  r.marking.style = MarkingStyle::kNone;
  r.viewport = {0, 0, eye.width, eye.height};
  return r;
}

// An axis-aligned square facing the eye at depth z, corners at (x0,y0)..(x1,y1), two triangles
// split along the (x0,y0)-(x1,y1) diagonal, with a texture of 2x2 blocks of four colours.
inline TexturedMesh facing_quad(double x0, double y0, double x1, double y1, double z) {
  TexturedMesh m;
  m.positions_m = {{float(x0), float(y0), float(z)},
                   {float(x1), float(y0), float(z)},
                   {float(x1), float(y1), float(z)},
                   {float(x0), float(y1), float(z)}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(4, 4);
  const uint8_t colours[4][3] = {{250, 0, 0}, {0, 250, 0}, {0, 0, 250}, {250, 250, 0}};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const uint8_t* c = colours[(y / 2) * 2 + (x / 2)];
      uint8_t* p = m.texture.pixel(x, y);
      p[0] = c[0];
      p[1] = c[1];
      p[2] = c[2];
      p[3] = 255;
    }
  }
  return m;
}

inline bool same_rgb(const uint8_t* p, uint8_t r, uint8_t g, uint8_t b) {
  return p[0] == r && p[1] == g && p[2] == b;
}

}  // namespace hd::render::test
