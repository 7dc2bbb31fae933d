#pragma once
// A small station for the tests that run whole frames (tests/station/*_no_allocation_test.cpp): one
// 160x120 mock camera at the world origin, a 500 Hz mock head, stereo 160x120 eyes and a
// transition band (m_t 8, eps 3, no lag) that the tests' head motions cross.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <utility>

#include "drivers/camera_source.h"
#include "drivers/mock/mock_camera.h"
#include "drivers/mock/mock_pose_source.h"
#include "drivers/pose_source.h"
#include "render/compositor/synthetic_scene.h"
#include "station/frame/station_frame.h"
#include "test_wait.h"

namespace hd::station::test {

inline core::Pinhole small_camera_intrinsics() {
  return core::Pinhole::centred(160, 160, 120);
}

inline drivers::MockCameraConfig small_camera_config() {
  drivers::MockCameraConfig cc;
  cc.width = 160;
  cc.height = 120;
  cc.rate_hz = 120.0;
  return cc;
}

inline drivers::MockPoseSourceConfig head_config(drivers::ScriptedMotion motion) {
  drivers::MockPoseSourceConfig pc;
  pc.motion = std::move(motion);
  pc.rate_hz = 500.0;
  return pc;
}

/// Head at `position_m(t)`, turned `yaw_rad(t)` about the vertical.
template <class Position, class Yaw>
drivers::ScriptedMotion head_motion(Position position_m, Yaw yaw_rad) {
  return [position_m, yaw_rad](double t_s) {
    drivers::TrajectorySample s;
    s.t_s = t_s;
    s.position_m = position_m(t_s);
    s.q = Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad(t_s), Eigen::Vector3d::UnitY()));
    return s;
  };
}

inline StationFrameConfig small_station_config(std::size_t max_rows) {
  StationFrameConfig cfg;
  cfg.rig = render::StereoRig();
  cfg.rig.eye = {core::Pinhole::centred(150, 160, 120), core::Pinhole::centred(150, 160, 120)};
  cfg.workspace.min_m = {-1, -1, 1};
  cfg.workspace.max_m = {1, 1, 3};
  cfg.transition.m_t = 8;
  cfg.transition.eps = 3;
  cfg.transition.time_constant_s = 0.0;
  cfg.max_rows = max_rows;
  return cfg;
}

/// A 2 m x 2 m quad 2 m ahead of the origin with an 8x8 texture of primary colours.
inline render::SyntheticScene checker_quad_scene() {
  render::SyntheticScene scene;
  render::TexturedMesh quad;
  quad.positions_m = {{-1, -1, 2}, {1, -1, 2}, {1, 1, 2}, {-1, 1, 2}};
  quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  quad.texture.allocate(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) quad.texture.pixel(x, y)[(x + y) % 3] = 255;
  scene.meshes.push_back(std::move(quad));
  return scene;
}

/// Opens and starts a camera and a head for a test's scope; stops both when it ends, also when
/// an assertion returns early. Returns once both have published their first frame and sample,
/// so a test's first tick never runs before the devices have spoken, however loaded the machine
/// is; if they stay silent (60 s, `eventually`'s bound on a hang) the test fails here, saying so.
class StartedDevices {
 public:
  StartedDevices(drivers::CameraSource& camera, drivers::PoseSource& head)
      : camera_(camera), head_(head) {
    camera_.open();
    head_.open();
    camera_.start();
    head_.start();
    if (!eventually(
            [&] { return camera_.frames().published() > 0 && head_.latest().published() > 0; })) {
      ADD_FAILURE() << "devices never spoke: camera published " << camera_.frames().published()
                    << ", head " << head_.latest().published();
    }
  }
  ~StartedDevices() { stop(); }
  StartedDevices(const StartedDevices&) = delete;
  StartedDevices& operator=(const StartedDevices&) = delete;
  void stop() {
    camera_.stop();
    head_.stop();
  }

 private:
  drivers::CameraSource& camera_;
  drivers::PoseSource& head_;
};

}  // namespace hd::station::test
