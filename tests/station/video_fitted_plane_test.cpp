// The fitted-plane view's d against scenes whose depths are known exactly: fronto-parallel
// quads at given distances from the camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "render/support/cpu_compositor_scenes.h"
#include "station/video/fitted_plane.h"

namespace {

using hd::core::Pinhole;
using hd::core::PixelRect;
using hd::core::Pose;
using hd::render::SyntheticScene;
using hd::render::test::facing_quad;
using hd::station::FittedPlane;

const Pinhole kCamera = Pinhole::centred(500.0, 640, 480);

TEST(FittedPlane, AWallFillingTheFrameGivesItsDistance) {
  SyntheticScene s;
  s.meshes.push_back(facing_quad(-3, -3, 3, 3, 2.0));
  FittedPlane f(kCamera, 1.0);
  EXPECT_NEAR(f.update(&s, Pose::identity(), nullptr, 0.0), 2.0, 1e-5);
}

TEST(FittedPlane, ASmallNearObjectLeavesThePlaneOnTheWall) {
  SyntheticScene s;
  s.meshes.push_back(facing_quad(-3, -3, 3, 3, 2.2));
  s.meshes.push_back(facing_quad(-0.2, -0.2, 0.2, 0.2, 1.0));  // ~17 % of the frame
  FittedPlane f(kCamera, 1.0);
  EXPECT_NEAR(f.update(&s, Pose::identity(), nullptr, 0.0), 2.2, 1e-5);
  // Only the board's part of the frame: the board.
  const PixelRect board{300, 220, 340, 260};
  FittedPlane g(kCamera, 1.0);
  EXPECT_NEAR(g.update(&s, Pose::identity(), &board, 0.0), 1.0, 1e-5);
}

TEST(FittedPlane, NoSurfaceInTheRegionKeepsD) {
  SyntheticScene s;
  s.meshes.push_back(facing_quad(0.5, -3, 3, 3, 2.0));  // right part of the frame only
  FittedPlane f(kCamera, 1.3);
  const PixelRect left{0, 0, 200, 480};
  EXPECT_EQ(f.update(&s, Pose::identity(), &left, 0.0), 1.3);
  EXPECT_EQ(f.update(nullptr, Pose::identity(), nullptr, 0.01), 1.3);
}

// The eye's part of the frame sweeps steadily from a wall at 2.2 m (left half) onto a board at
// 1.0 m (right half) in 2 s at 90 Hz: the median jumps by 1.2 m in one frame, d never moves more
// than the lag allows, 1.2 m (1 - exp(-dt / tau)) = 6.5 cm, and settles on the board.
TEST(FittedPlane, DMovesSmoothlyWhileTheViewSweepsAcrossADepthEdge) {
  SyntheticScene s;
  s.meshes.push_back(facing_quad(-3, -3, 0, 3, 2.2));
  s.meshes.push_back(facing_quad(0, -3, 3, 3, 1.0));
  FittedPlane f(kCamera, 1.0);
  const double dt = 1.0 / 90.0;
  double d_prev = NAN, target_prev = NAN, max_step = 0.0, max_target_step = 0.0;
  for (int i = 0; i <= 270; ++i) {
    const double u0 = std::min(1.0, i / 180.0) * 480.0;  // a 160 px wide window, left to right
    const PixelRect region{u0, 0, u0 + 160.0, 480};
    const double d = f.update(&s, Pose::identity(), &region, i == 0 ? 0.0 : dt);
    if (i > 0) {
      max_step = std::max(max_step, std::abs(d - d_prev));
      max_target_step = std::max(max_target_step, std::abs(f.target_m() - target_prev));
    }
    d_prev = d;
    target_prev = f.target_m();
  }
  const double bound = 1.2 * (1.0 - std::exp(-dt / FittedPlane::kTimeConstant_s));
  std::printf("    largest step: d %.4f m (bound %.4f), median %.4f m\n", max_step, bound,
              max_target_step);
  EXPECT_NEAR(max_target_step, 1.2, 1e-4);    // the unsmoothed choice jumps
  EXPECT_LE(max_step, bound * (1.0 + 1e-6));  // depths are floats
  EXPECT_GT(max_step, 0.5 * bound);           // and d does follow it
  EXPECT_NEAR(d_prev, 1.0, 0.01);             // 1 s after the sweep: on the board
}

}  // namespace
