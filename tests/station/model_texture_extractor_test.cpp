// Projective texturing checked against independent geometry: a textured plane rendered from a
// camera by the CPU compositor is extracted back into a blank texture; which texels a box hides
// and which fall outside the image is decided by ray/box and projection tests written here.
#include <gtest/gtest.h>

#include <cmath>

#include "render/compositor/cpu_compositor.h"
#include "station/model/texture_extractor.h"

namespace hd::station {
namespace {

constexpr int kTexW = 256, kTexH = 192;             // 7.8125 mm texels on a 2 m x 1.5 m plane
constexpr uint8_t kSentinel[4] = {10, 20, 30, 77};  // "never written": alpha 77

// Plane z = 2, x in [-1, 1], y in [-0.75, 0.75]; texture s along x, t along y (row 0 at the top).
Eigen::Vector3d plane_point(double s, double t) {
  return {-1.0 + 2.0 * s, -0.75 + 1.5 * t, 2.0};
}

// Smooth colours (period 16 / 16 / 24 texels): bilinear reconstruction errs little on them,
// yet a half-texel misregistration would cost ~18 DN (see the PSNR bound below).
std::array<uint8_t, 3> pattern(int i, int j) {
  const double x = i + 0.5, y = j + 0.5;
  return {static_cast<uint8_t>(std::lround(128 + 90 * std::sin(2 * M_PI * x / 16))),
          static_cast<uint8_t>(std::lround(128 + 90 * std::sin(2 * M_PI * y / 16))),
          static_cast<uint8_t>(std::lround(128 + 60 * std::sin(2 * M_PI * (x + y) / 24)))};
}

render::TexturedMesh make_plane(bool blank) {
  render::TexturedMesh m;
  m.positions_m = {plane_point(0, 0).cast<float>(), plane_point(1, 0).cast<float>(),
                   plane_point(1, 1).cast<float>(), plane_point(0, 1).cast<float>()};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(kTexW, kTexH);
  for (int j = 0; j < kTexH; ++j)
    for (int i = 0; i < kTexW; ++i) {
      uint8_t* p = m.texture.pixel(i, j);
      const auto c = pattern(i, j);
      for (int k = 0; k < 3; ++k) p[k] = blank ? kSentinel[k] : c[static_cast<std::size_t>(k)];
      p[3] = blank ? kSentinel[3] : 255;
    }
  return m;
}

struct Box {
  Eigen::Vector3d lo, hi;
};

render::TexturedMesh make_box(const Box& b) {
  render::TexturedMesh m;
  for (int k = 0; k < 8; ++k)
    m.positions_m.push_back(Eigen::Vector3d(k & 1 ? b.hi.x() : b.lo.x(),
                                            k & 2 ? b.hi.y() : b.lo.y(),
                                            k & 4 ? b.hi.z() : b.lo.z())
                                .cast<float>());
  for (int k = 0; k < 8; ++k) m.uvs.push_back({(k & 1) ? 1.0f : 0.0f, (k & 2) ? 1.0f : 0.0f});
  const std::array<std::array<uint32_t, 4>, 6> faces = {
      {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  m.texture.allocate(4, 4);
  for (auto& v : m.texture.data) v = 90;
  return m;
}

// Does the segment a -> b meet the axis-aligned box? (slab test)
bool segment_hits(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Box& box) {
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; ++k) {
    const double d = b[k] - a[k];
    if (std::abs(d) < 1e-15) {
      if (a[k] < box.lo[k] || a[k] > box.hi[k]) return false;
      continue;
    }
    double ta = (box.lo[k] - a[k]) / d, tb = (box.hi[k] - a[k]) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

drivers::Frame render_view(const render::SyntheticScene& scene, const core::Pinhole& k,
                           const core::Pose& pose) {
  render::CpuCompositor compositor(1);
  render::ImageRgba8 out;
  out.allocate(k.width, k.height);
  render::CompositeRequest req;
  req.scene = &scene;
  req.eye = k;
  req.T_world_eye = pose;
  req.marking.style = core::MarkingStyle::kNone;
  req.viewport = {0, 0, k.width, k.height};
  compositor.draw(req, out);
  drivers::Frame f;
  f.allocate_rgba(k.width, k.height);
  f.data = out.data;
  f.host_timestamp_ns = 1;
  return f;
}

core::Pose yaw_pose(double yaw_deg, const Eigen::Vector3d& centre) {
  return {Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix(),
          centre};
}

TEST(ModelTextureExtractor, PlaneRenderedByTheCompositorComesBackWhereVisibleOnly) {
  const core::Pinhole k = core::Pinhole::centred(300, 320, 240);
  const core::Pose cam = yaw_pose(12, {0.35, 0.0, 0.0});  // left part of the plane out of view
  const Box box{{0.4, 0.0, 1.2}, {0.6, 0.2, 1.4}};        // hides a patch around x~0.6, y~0.15
  render::SyntheticScene truth;
  truth.meshes = {make_plane(false), make_box(box)};
  const drivers::Frame frame = render_view(truth, k, cam);

  render::SyntheticScene model;
  model.meshes = {make_plane(true), make_box(box)};
  TextureExtractor ex;
  ex.prepare(model);
  const ExtractionView view{&frame, k, cam};
  ASSERT_TRUE(ex.extract(model, std::span(&view, 1)));
  EXPECT_EQ(ex.last_stats().views_used, 1u);

  // Independent classification of every plane texel, with margins of a few texels around the
  // silhouettes (the extractor's footprint and depth-bias rules act there).
  const double margin_m = 0.02;
  const Box shrunk{box.lo.array() + margin_m, box.hi.array() - margin_m};
  const Box grown{box.lo.array() - margin_m, box.hi.array() + margin_m};
  int occluded = 0, outside = 0, visible = 0;
  double sq_err = 0.0;
  const render::ImageRgba8& tex = model.meshes[0].texture;
  for (int j = 0; j < kTexH; ++j)
    for (int i = 0; i < kTexW; ++i) {
      const Eigen::Vector3d X = plane_point((i + 0.5) / kTexW, (j + 0.5) / kTexH);
      const Eigen::Vector2d uv = k.project(cam.to_camera(X));
      const uint8_t* got = tex.pixel(i, j);
      const bool untouched = got[0] == kSentinel[0] && got[1] == kSentinel[1] &&
                             got[2] == kSentinel[2] && got[3] == kSentinel[3];
      if (uv.x() < -1 || uv.y() < -1 || uv.x() > k.width + 1 || uv.y() > k.height + 1) {
        ++outside;
        EXPECT_TRUE(untouched) << "out-of-view texel " << i << "," << j << " was written";
      } else if (segment_hits(cam.t, X, shrunk)) {
        ++occluded;
        EXPECT_TRUE(untouched) << "occluded texel " << i << "," << j << " was written";
      } else if (!segment_hits(cam.t, X, grown) && uv.x() > 3 && uv.y() > 3 &&
                 uv.x() < k.width - 3 && uv.y() < k.height - 3) {
        ++visible;
        ASSERT_EQ(got[3], 255) << "visible texel " << i << "," << j << " not updated";
        const auto want = pattern(i, j);
        for (int c = 0; c < 3; ++c) {
          const double e = static_cast<double>(got[c]) - want[static_cast<std::size_t>(c)];
          sq_err += e * e;
        }
      }
    }
  ASSERT_GT(occluded, 300);  // the box really hides a patch
  ASSERT_GT(outside, 3000);  // and the camera really misses part of the plane
  ASSERT_GT(visible, 20000);
  const double mse = sq_err / (3.0 * visible);
  const double psnr_db = 10 * std::log10(255.0 * 255.0 / mse);
  // Bound: render and extraction each interpolate bilinearly at about one sample per texel. For
  // a sinusoid of amplitude A and period P samples the linear-interpolation error is at most
  // A (2 pi / P)^2 / 8 = 90 * 0.154 / 8 = 1.7 DN, so two passes plus two roundings stay below
  // ~4.5 DN everywhere: PSNR > 35 dB. 30 dB (RMS 8 DN) leaves margin, and still fails for a
  // half-texel misregistration (error amplitude 90 * 2 pi / 16 * 0.5 = 17.7 DN, RMS ~12 DN).
  EXPECT_GE(psnr_db, 30.0) << "mse " << mse;
  RecordProperty("psnr_db", std::to_string(psnr_db));
  EXPECT_GE(ex.last_stats().texels_updated, static_cast<uint64_t>(visible));
}

TEST(ModelTextureExtractor, TheMostFrontalCameraWinsWhateverTheOrder) {
  const core::Pinhole k = core::Pinhole::centred(300, 320, 240);
  const core::Pose a = core::Pose::identity();
  const core::Pose b = yaw_pose(-35, {1.2, 0.0, 0.8});
  drivers::Frame red, blue;
  red.allocate_rgba(k.width, k.height);
  blue.allocate_rgba(k.width, k.height);
  for (std::size_t p = 0; p < red.data.size(); p += 4) {
    red.data[p] = 200;
    blue.data[p + 2] = 200;
  }
  const ExtractionView ab[] = {{&red, k, a}, {&blue, k, b}};
  const ExtractionView ba[] = {{&blue, k, b}, {&red, k, a}};
  for (const auto* views : {ab, ba}) {
    render::SyntheticScene model;
    model.meshes = {make_plane(true)};
    TextureExtractor ex;
    ex.prepare(model);
    ASSERT_TRUE(ex.extract(model, std::span(views, 2)));
    int red_won = 0, blue_won = 0;
    for (int j = 4; j < kTexH - 4; ++j)
      for (int i = 4; i < kTexW - 4; ++i) {
        const Eigen::Vector3d X = plane_point((i + 0.5) / kTexW, (j + 0.5) / kTexH);
        // Inside the image by `margin` pixels (negative: up to that far outside).
        auto sees = [&](const core::Pose& cam, double margin, double& cos) {
          const Eigen::Vector3d c = cam.to_camera(X);
          const Eigen::Vector2d uv = k.project(c);
          cos = std::abs((cam.t - X).normalized().z());  // plane normal is the z axis
          return c.z() > 0 && uv.x() > margin && uv.y() > margin && uv.x() < k.width - margin &&
                 uv.y() < k.height - margin;
        };
        double ca = 0, cb = 0;
        const bool in_a = sees(a, 2, ca), in_b = sees(b, 2, cb);
        const bool maybe_a = sees(a, -1, ca), maybe_b = sees(b, -1, cb);
        const uint8_t* got = model.meshes[0].texture.pixel(i, j);
        if (in_a && (!maybe_b || ca > cb + 0.01)) {
          EXPECT_EQ(got[0], 200) << i << "," << j;
          red_won += got[0] == 200;
        } else if (in_b && (!maybe_a || cb > ca + 0.01)) {
          EXPECT_EQ(got[2], 200) << i << "," << j;
          blue_won += got[2] == 200;
        }
      }
    EXPECT_GT(red_won, 5000);
    EXPECT_GT(blue_won, 2000);
  }
}

TEST(ModelTextureExtractor, FollowsMovedGeometryAndRejectsBadViewsAndShapes) {
  const core::Pinhole k = core::Pinhole::centred(300, 320, 240);
  // The plane moved 0.3 m right since the extractor was prepared: the texel's point moves too.
  render::SyntheticScene truth;
  truth.meshes = {make_plane(false)};
  for (auto& p : truth.meshes[0].positions_m) p.x() += 0.3f;
  const drivers::Frame frame = render_view(truth, k, core::Pose::identity());
  render::SyntheticScene model;
  model.meshes = {make_plane(true)};
  TextureExtractor ex;
  ex.prepare(model);
  model.meshes[0].positions_m = truth.meshes[0].positions_m;
  const ExtractionView view{&frame, k, core::Pose::identity()};
  ASSERT_TRUE(ex.extract(model, std::span(&view, 1)));
  double sq = 0;
  int n = 0;
  for (int j = 20; j < kTexH - 20; ++j)
    for (int i = 20; i < 200; ++i) {  // x up to ~0.87 m: inside the image (edge at 1.07 m)
      const auto want = pattern(i, j);
      const uint8_t* got = model.meshes[0].texture.pixel(i, j);
      for (int c = 0; c < 3; ++c) {
        const double e = static_cast<double>(got[c]) - want[static_cast<std::size_t>(c)];
        sq += e * e;
      }
      ++n;
    }
  EXPECT_GE(10 * std::log10(255.0 * 255.0 * 3 * n / sq), 30.0);

  drivers::Frame wrong;
  wrong.allocate_rgba(100, 100);
  const ExtractionView bad[] = {{nullptr, k, core::Pose::identity()},
                                {&wrong, k, core::Pose::identity()},
                                {&frame, k, core::Pose{Eigen::Matrix3d::Zero(), {0, 0, 0}}}};
  render::SyntheticScene copy = model;
  ASSERT_TRUE(ex.extract(copy, bad));
  EXPECT_EQ(ex.last_stats().views_rejected, 3u);
  EXPECT_EQ(ex.last_stats().texels_updated, 0u);
  EXPECT_EQ(copy.meshes[0].texture.data, model.meshes[0].texture.data);

  copy.meshes[0].texture.allocate(64, 64);  // another texture size: not what was prepared
  EXPECT_FALSE(ex.extract(copy, std::span(&view, 1)));
}

}  // namespace
}  // namespace hd::station
