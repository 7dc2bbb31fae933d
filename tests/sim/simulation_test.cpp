// The simulation as the station sees it: devices named sim:<name> that stream frames of the scene
// on a shared clock, station camera data, and the model with its moving objects.

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "sim/scene/scene_file.h"
#include "sim/simulation.h"
#include "test_paths.h"

namespace hd::sim {
namespace {

const std::filesystem::path kScenes = std::filesystem::path(hd::test::source_dir()) / "scenes";

Scene small_default() {
  // The default scene at a tenth of the resolution keeps the test fast under sanitizers.
  Scene s = load_scene((kScenes / "bare.yaml").string());
  for (SceneCamera& c : s.cameras) {
    c.p_c.fx /= 4;
    c.p_c.fy /= 4;
    c.p_c.cx /= 4;
    c.p_c.cy /= 4;
    c.p_c.width /= 4;
    c.p_c.height /= 4;
  }
  return s;
}

TEST(Simulation, DevicesAreNamedAfterTheScene) {
  Simulation sim(small_default());
  ASSERT_EQ(sim.camera_count(), 2u);
  EXPECT_EQ(sim.camera(0).id(), "sim:cam0");
  EXPECT_EQ(sim.camera(1).id(), "sim:cam1");
  EXPECT_EQ(sim.head().id(), "sim:head");
  const auto cams = sim.station_cameras();
  ASSERT_EQ(cams.size(), 2u);
  EXPECT_EQ(cams[1].source, &sim.camera(1));
  EXPECT_DOUBLE_EQ(cams[1].d_m, 1.6);
  EXPECT_EQ(cams[1].p_c.width, 160);
  EXPECT_TRUE(cams[1].T_world_real.valid());
}

TEST(Simulation, ModelHoldsStaticGeometryAndObjectsAtTimeZero) {
  Simulation sim(small_default());
  // table + wall (one quad each) + gripper + block (six faces each)
  ASSERT_EQ(sim.model().meshes.size(), 2u + 6u + 6u);
  for (const render::TexturedMesh& m : sim.model().meshes) EXPECT_TRUE(m.valid());
  // The block's 24 vertices average to its centre (-0.3, 0.36, 1.3), as its keyframe says.
  auto centre_of = [](const render::SyntheticScene& s, std::size_t first) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    int n = 0;
    for (std::size_t m = first; m < first + 6; ++m) {
      for (const Eigen::Vector3f& v : s.meshes[m].positions_m) {
        c += v.cast<double>();
        ++n;
      }
    }
    return Eigen::Vector3d(c / n);
  };
  EXPECT_LT((centre_of(sim.model(), 8) - Eigen::Vector3d(-0.3, 0.36, 1.3)).norm(), 1e-6);
  // At 7 s the gripper is 2/3 of the way from (-0.3, 0.10, 1.3) (t = 5) to (0.3, 0.10, 1.5)
  // (t = 8) and the block hangs 0.09 m below it.
  render::SyntheticScene moved = sim.model();
  const uint64_t revision = moved.revision;
  sim.place_objects(moved, 7.0);
  EXPECT_GT(moved.revision, revision);
  const Eigen::Vector3d gripper(-0.3 + 0.6 * 2 / 3.0, 0.10, 1.3 + 0.2 * 2 / 3.0);
  EXPECT_LT((centre_of(moved, 2) - gripper).norm(), 1e-6);
  EXPECT_LT((centre_of(moved, 8) - (gripper + Eigen::Vector3d(0, 0.09, 0))).norm(), 1e-6);
  // Static geometry is not moved.
  EXPECT_EQ(moved.meshes[0].positions_m, sim.model().meshes[0].positions_m);
}

TEST(Simulation, RenderedBlockMovesWithItsKeyframes) {
  Simulation sim(small_default());
  // cam0 frame at 0 s and at 7 s (sequence 210 at 30 Hz): the block's red pixels move right.
  auto red_centroid_x = [](const drivers::Frame& f) {
    double sx = 0;
    int n = 0;
    for (int y = 0; y < f.height; ++y) {
      for (int x = 0; x < f.width; ++x) {
        const uint8_t* p = f.data.data() + static_cast<std::size_t>(y) * f.stride_bytes + 4 * x;
        if (p[0] > 100 && p[1] < 70 && p[2] < 70) {
          sx += x + 0.5;
          ++n;
        }
      }
    }
    return n > 0 ? sx / n : -1.0;
  };
  drivers::Frame f0, f7;
  sim.render_frame(0, 0, f0);
  sim.render_frame(0, 210, f7);
  EXPECT_EQ(f7.host_timestamp_ns, int64_t{210} * 33'333'333);  // 30 Hz grid
  const core::Pinhole& k = sim.scene().cameras[0].p_c;
  const core::Pose& P = sim.scene().cameras[0].T_world_cam;
  const double u0 = k.project(P.to_camera({-0.3, 0.36, 1.3})).x();
  const double u7 = k.project(P.to_camera({0.1, 0.19, 1.3 + 0.2 * 2 / 3.0})).x();
  EXPECT_NEAR(red_centroid_x(f0), u0, 1.5);
  EXPECT_NEAR(red_centroid_x(f7), u7, 1.5);
}

TEST(Simulation, DevicesStreamOnTheSharedClock) {
  Simulation sim(small_default());
  sim.start();
  const int64_t epoch = sim.epoch_ns();
  EXPECT_GT(epoch, 0);
  drivers::Mailbox<drivers::Frame>& frames = sim.camera(0).frames();
  bool got = false;
  for (int i = 0; i < 6000 && !got; ++i) {  // up to 60 s under load; not a timing assertion
    got = frames.fetch();
    if (!got) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  bool pose = false;
  for (int i = 0; i < 6000 && !pose; ++i) {
    pose = sim.head().latest().fetch();
    if (!pose) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  sim.stop();
  ASSERT_TRUE(got);
  ASSERT_TRUE(pose);
  const drivers::Frame& f = frames.latest();
  EXPECT_EQ(f.width, 160);
  EXPECT_EQ(f.height, 120);
  EXPECT_TRUE(f.device_time_trusted);
  // Exposures lie on the 30 Hz grid from the epoch.
  const int64_t period = 33'333'333;
  EXPECT_EQ((f.host_timestamp_ns - epoch) % period, 0) << f.host_timestamp_ns - epoch;
  const int64_t head_period = 2'000'000;  // 500 Hz
  EXPECT_EQ((sim.head().latest().latest().host_timestamp_ns - epoch) % head_period, 0);
  // The pixels are the offline render of the same time.
  drivers::Frame offline;
  const auto seq = static_cast<uint64_t>((f.host_timestamp_ns - epoch) / period);
  sim.render_frame(0, seq, offline);
  EXPECT_TRUE(offline.data == f.data);
}

TEST(Simulation, HeadMotionStartsOverWhenTheSceneLoops) {
  Scene once = small_default();
  Scene looped = small_default();
  looped.loop = true;
  const Simulation a(std::move(once));
  const Simulation b(std::move(looped));
  const double lap = b.scene().duration_s;
  auto gap = [](const drivers::PoseSample& x, const drivers::PoseSample& y) {
    return (x.T_tracker_head.t - y.T_tracker_head.t).norm() +
           Eigen::AngleAxisd(x.T_tracker_head.R.transpose() * y.T_tracker_head.R).angle();
  };
  // Within the first lap both are the same motion.
  EXPECT_EQ(gap(a.head_sample(7.0, 0), b.head_sample(7.0, 0)), 0.0);
  // After it, the scene that does not loop holds the last pose; the looped one is where it was
  // a lap earlier, moving at the same rate (the angular velocity is of the second lap too).
  EXPECT_EQ(gap(a.head_sample(lap + 7.0, 0), a.head_sample(lap, 0)), 0.0);
  EXPECT_GT(gap(a.head_sample(7.0, 0), a.head_sample(lap + 7.0, 0)), 0.1);
  const drivers::PoseSample first = b.head_sample(7.0, 0);
  const drivers::PoseSample third = b.head_sample(2 * lap + 7.0, 0);
  EXPECT_NEAR(gap(first, third), 0.0, 1e-9);
  EXPECT_NEAR((first.angular_velocity_rad_s - third.angular_velocity_rad_s).norm(), 0.0, 1e-6);
  EXPECT_GT(first.angular_velocity_rad_s.norm(), 0.01);
  // The default motion ends where it starts, so the lap boundary is not a jump.
  EXPECT_NEAR(gap(b.head_sample(lap - 1e-3, 0), b.head_sample(lap + 1e-3, 0)), 0.0, 1e-6);
}

}  // namespace
}  // namespace hd::sim
