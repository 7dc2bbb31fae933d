// The CPU reference compositor's synthetic model against independent expectations: a quad's
// projection and texture, the top-left fill rule, perspective-correct interpolation, near-plane
// clipping and the depth test.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "support/cpu_compositor_scenes.h"

namespace {

using namespace hd::render::test;

TEST(CpuCompositor, FacingQuadCoversExactlyItsProjectionWithItsTextureColours) {
  // f = 400, 640x480, quad 1 m x 1 m at 2 m: projects to u in [220, 420], v in [140, 340].
  const Pinhole eye = pinhole(400.0, 640, 480);
  SyntheticScene scene;
  scene.background_rgb = {10, 20, 30};
  scene.meshes.push_back(facing_quad(-0.5, -0.5, 0.5, 0.5, 2.0));
  CpuCompositor comp;
  ImageRgba8 out;
  out.allocate(640, 480);
  CompositeRequest req;
  req.scene = &scene;
  req.eye = eye;
  req.marking.style = MarkingStyle::kNone;
  req.viewport = {0, 0, 640, 480};
  comp.draw(req, out);
  int covered = 0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) covered += same_rgb(out.pixel(x, y), 10, 20, 30) ? 0 : 1;
  }
  EXPECT_EQ(covered, 200 * 200);
  EXPECT_TRUE(same_rgb(out.pixel(220, 140), 250, 0, 0));    // top-left block
  EXPECT_TRUE(same_rgb(out.pixel(419, 140), 0, 250, 0));    // top-right
  EXPECT_TRUE(same_rgb(out.pixel(220, 339), 0, 0, 250));    // bottom-left
  EXPECT_TRUE(same_rgb(out.pixel(419, 339), 250, 250, 0));  // bottom-right
  EXPECT_TRUE(same_rgb(out.pixel(219, 200), 10, 20, 30));
  EXPECT_TRUE(same_rgb(out.pixel(420, 200), 10, 20, 30));
  EXPECT_EQ(comp.stats().frames_drawn, 1u);
}

TEST(CpuCompositor, TopLeftRuleCoversEachCentreOnSharedAndOuterEdgesExactlyOnce) {
  // Corners at half-integer pixels (u = 220.5 .. 420.5): every edge, including the shared
  // diagonal, passes through pixel centres. Top/left edges own them: 200 x 200 pixels, no holes.
  const Pinhole eye = pinhole(200.0, 640, 480);
  SyntheticScene scene;
  scene.background_rgb = {10, 20, 30};
  const double a = (220.5 - 320.0) / 100.0, b = (420.5 - 320.0) / 100.0;
  const double c = (140.5 - 240.0) / 100.0, d = (340.5 - 240.0) / 100.0;
  scene.meshes.push_back(facing_quad(a, c, b, d, 2.0));
  const ImageRgba8 out = draw_model(scene, eye);
  int covered = 0, holes = 0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      const bool drawn = !same_rgb(out.pixel(x, y), 10, 20, 30);
      covered += drawn ? 1 : 0;
      const bool expect = x >= 220 && x < 420 && y >= 140 && y < 340;
      holes += (expect && !drawn) ? 1 : 0;
    }
  }
  EXPECT_EQ(covered, 200 * 200);
  EXPECT_EQ(holes, 0);
}

TEST(CpuCompositor, TiltedQuadIsInterpolatedPerspectiveCorrectly) {
  // A floor strip from z = 1 m to z = 3 m at y = 0.5 m below the eye; texture t runs with z, its
  // rows hold the value of their index (t * 256). The world midpoint z = 2 m (t = 0.5) projects
  // to v = cy + f * 0.5 / 2; affine interpolation would put t = 0.5 at the screen midpoint.
  const Pinhole eye = pinhole(200.0, 320, 240);
  TexturedMesh m;
  m.positions_m = {{-1, 0.5f, 1}, {1, 0.5f, 1}, {1, 0.5f, 3}, {-1, 0.5f, 3}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.texture.allocate(1, 256);
  for (int j = 0; j < 256; ++j) {
    uint8_t* p = m.texture.pixel(0, j);
    p[0] = p[1] = p[2] = static_cast<uint8_t>(j);
    p[3] = 255;
  }
  SyntheticScene scene;
  scene.meshes.push_back(m);
  const ImageRgba8 out = draw_model(scene, eye);
  // Rows: z = f * 0.5 / (v - cy). Check several rows against t = (z - 1) / 2 exactly.
  for (int row : {150, 160, 170, 180, 200, 220}) {
    const double v = row + 0.5;
    const double z = 200.0 * 0.5 / (v - 120.0);
    if (z < 1.0 || z > 3.0) continue;
    const double t = (z - 1.0) / 2.0;
    const double expected = std::clamp(t * 256.0 - 0.5, 0.0, 255.0);  // bilinear between rows
    EXPECT_NEAR(out.pixel(160, row)[0], expected, 1.0) << "row " << row;
  }
}

TEST(CpuCompositor, TriangleCrossingTheNearPlaneIsClippedNotDropped) {
  // A wall in the plane x = 0.3 running from behind the eye (z = -1) to z = 5.
  const Pinhole eye = pinhole(200.0, 320, 240);
  TexturedMesh m = facing_quad(0, 0, 1, 1, 1);
  m.positions_m = {{0.3f, -1, -1}, {0.3f, -1, 5}, {0.3f, 1, 5}, {0.3f, 1, -1}};
  SyntheticScene scene;
  scene.background_rgb = {0, 0, 0};
  scene.meshes.push_back(m);
  const ImageRgba8 out = draw_model(scene, eye, 0.1);
  // At the image row through the centre the wall spans u from 160 + 200*0.3/5 = 172 to the
  // right edge (u -> inf as z -> 0).
  EXPECT_TRUE(same_rgb(out.pixel(170, 120), 0, 0, 0));
  EXPECT_FALSE(same_rgb(out.pixel(175, 120), 0, 0, 0));
  EXPECT_FALSE(same_rgb(out.pixel(319, 120), 0, 0, 0));
}

TEST(CpuCompositor, NearerSurfaceWinsTheDepthTestWhateverTheDrawOrder) {
  const Pinhole eye = pinhole(200.0, 160, 120);
  TexturedMesh near_q = facing_quad(-0.2, -0.2, 0.2, 0.2, 1.0);  // red block in the middle
  TexturedMesh far_q = facing_quad(-2.0, -2.0, 2.0, 2.0, 3.0);
  for (std::size_t i = 0; i < far_q.texture.data.size(); i += 4) {  // all green
    far_q.texture.data[i] = 0;
    far_q.texture.data[i + 1] = 250;
    far_q.texture.data[i + 2] = 0;
  }
  for (int order = 0; order < 2; ++order) {
    SyntheticScene scene;
    scene.meshes =
        order ? std::vector<TexturedMesh>{near_q, far_q} : std::vector<TexturedMesh>{far_q, near_q};
    const ImageRgba8 out = draw_model(scene, eye);
    // Inside the near quad's top-left (red) block; the far quad is all green.
    const uint8_t* p = out.pixel(50, 30);
    EXPECT_TRUE(same_rgb(p, 250, 0, 0)) << order;
    EXPECT_TRUE(same_rgb(out.pixel(150, 110), 0, 250, 0)) << order;  // only the far quad there
  }
}

}  // namespace
