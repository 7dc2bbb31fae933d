#pragma once
// Test helper: a stereo pair of a scene of textured rectangles, rendered by the station's own CPU
// rasteriser from known pinholes and poses, with the rectangles kept for closed-form distances.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "core/pinhole.h"
#include "core/pose.h"
#include "recon/stereo_rig.h"
#include "render/compositor/mesh_rasterizer.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::recon::testing {

/// A rectangle: corner + two edge vectors (world metres).
struct Rect3 {
  Eigen::Vector3d origin, u, v;

  double distance(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = p - origin;
    const double a = std::clamp(d.dot(u) / u.squaredNorm(), 0.0, 1.0);
    const double b = std::clamp(d.dot(v) / v.squaredNorm(), 0.0, 1.0);
    return (p - (origin + a * u + b * v)).norm();
  }
};

/// Smooth random texture (features of a few texels), seeded: what stereo needs to match.
inline render::ImageRgba8 noise_texture(int size, uint64_t seed, int base = 128, int amp = 90) {
  cv::Mat n(size, size, CV_32F);
  cv::RNG rng(seed);
  rng.fill(n, cv::RNG::UNIFORM, -1.0, 1.0);
  cv::GaussianBlur(n, n, cv::Size(0, 0), 1.2);
  double lo, hi;
  cv::minMaxLoc(n, &lo, &hi);
  render::ImageRgba8 t;
  t.allocate(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double s = (n.at<float>(y, x) - lo) / (hi - lo) * 2.0 - 1.0;
      const int g = std::clamp(static_cast<int>(base + amp * s), 0, 255);
      uint8_t* p = t.pixel(x, y);
      p[0] = static_cast<uint8_t>(g);
      p[1] = static_cast<uint8_t>(std::clamp(g + 20, 0, 255));
      p[2] = static_cast<uint8_t>(std::clamp(255 - g, 0, 255));
      p[3] = 255;
    }
  return t;
}

inline render::ImageRgba8 plain_texture(uint8_t grey) {
  render::ImageRgba8 t;
  t.allocate(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      uint8_t* p = t.pixel(x, y);
      p[0] = p[1] = p[2] = grey;
      p[3] = 255;
    }
  return t;
}

class RenderedScene {
 public:
  /// Adds a rectangle (corner, edges) with a texture to the scene.
  void add(const Rect3& r, render::ImageRgba8 texture) {
    render::TexturedMesh m;
    for (const Eigen::Vector3d& p :
         {r.origin, Eigen::Vector3d(r.origin + r.u), Eigen::Vector3d(r.origin + r.u + r.v),
          Eigen::Vector3d(r.origin + r.v)})
      m.positions_m.push_back(p.cast<float>());
    m.uvs = {{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.texture = std::move(texture);
    scene_.meshes.push_back(std::move(m));
    rects_.push_back(r);
  }
  /// The six faces of an axis-aligned (in `frame`) box centred at c with edge lengths s.
  void add_box(const core::Pose& frame, const Eigen::Vector3d& c, const Eigen::Vector3d& s,
               uint64_t seed) {
    const Eigen::Vector3d h = s / 2;
    const Eigen::Vector3d ex(s.x(), 0, 0), ey(0, s.y(), 0), ez(0, 0, s.z());
    const Eigen::Vector3d lo = c - h;
    auto put = [&](const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
                   uint64_t k) {
      add({frame.to_world(o), frame.R * u, frame.R * v}, noise_texture(256, seed + k));
    };
    put(lo, ex, ey, 0);       // front (z = lo.z)
    put(lo + ez, ex, ey, 1);  // back
    put(lo, ex, ez, 2);       // top (y = lo.y: y is down)
    put(lo + ey, ex, ez, 3);  // bottom
    put(lo, ey, ez, 4);       // left
    put(lo + ex, ey, ez, 5);  // right
  }

  const std::vector<Rect3>& rects() const { return rects_; }

  double distance(const Eigen::Vector3d& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const Rect3& r : rects_) d = std::min(d, r.distance(p));
    return d;
  }

  /// BGR image (CV_8UC3) and depth along the camera's z (CV_32F, 0 = nothing) seen by `cam`.
  void render(const core::Pinhole& cam, const core::Pose& T_world_cam, cv::Mat& bgr,
              cv::Mat& depth) const {
    render::MeshRasterizer r;
    r.prepare(scene_, cam, T_world_cam, 0.05, 100.0);
    std::vector<uint8_t> rgba(static_cast<std::size_t>(cam.width * cam.height * 4), 0);
    cv::Mat inv(cam.height, cam.width, CV_32F, cv::Scalar(0));
    render::RasterTarget t{rgba.data(), inv.ptr<float>(), cam.width, cam.height};
    r.draw_rows(scene_, t, 0, cam.height);
    const cv::Mat wrapped(cam.height, cam.width, CV_8UC4, rgba.data());
    cv::cvtColor(wrapped, bgr, cv::COLOR_RGBA2BGR);
    depth.create(inv.size(), CV_32F);
    for (int y = 0; y < inv.rows; ++y)
      for (int x = 0; x < inv.cols; ++x) {
        const float v = inv.at<float>(y, x);
        depth.at<float>(y, x) = v > 0 ? 1.0f / v : 0.0f;
      }
  }

 private:
  render::SyntheticScene scene_;
  std::vector<Rect3> rects_;
};

/// The test rig: two 640x480 cameras (f = 500 px) 0.12 m apart side by side, placed in the world
/// by T_world_rig (the rig frame: the left camera's axes, origin midway between the cameras).
inline StereoRig test_rig(const core::Pose& T_world_rig) {
  StereoRig rig;
  rig.left = rig.right = core::Pinhole::centred(500.0, 640, 480);
  rig.T_world_left = T_world_rig * core::Pose{Eigen::Matrix3d::Identity(), {-0.06, 0, 0}};
  rig.T_world_right = T_world_rig * core::Pose{Eigen::Matrix3d::Identity(), {0.06, 0, 0}};
  return rig;
}

/// A tilted, shifted rig pose: exercises P_c rather than an identity.
inline core::Pose tilted_rig_pose() {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return {R, {0.4, -0.3, 0.25}};
}

/// The standard test scene in the rig frame: a back wall at z = 2.2, a floor at y = 0.45, a box
/// in the middle, all noise-textured.
inline void add_standard_scene(RenderedScene& s, const core::Pose& T_world_rig) {
  auto rect = [&](const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    return Rect3{T_world_rig.to_world(o), T_world_rig.R * u, T_world_rig.R * v};
  };
  s.add(rect({-2.0, -1.5, 2.2}, {4.0, 0, 0}, {0, 1.95, 0}), noise_texture(1024, 11));
  s.add(rect({-2.0, 0.45, 0.5}, {4.0, 0, 0}, {0, 0, 1.7}), noise_texture(1024, 12));
  s.add_box(T_world_rig, {0.1, 0.2, 1.4}, {0.35, 0.5, 0.3}, 20);
}

}  // namespace hd::recon::testing
