// The station assembled from a scene file and from station.yaml: one record per camera, each
// wired to its own pipeline, with the calibration, age bound and link its description gives.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/video_age.h"
#include "sim/scene/scene_file.h"
#include "station/app/station_config.h"
#include "station/app/station_parts.h"
#include "test_paths.h"

namespace hd::station {
namespace {

namespace fs = std::filesystem;

sim::Scene default_scene() {
  return sim::load_scene(std::string(hd::test::source_dir()) + "/scenes/default.yaml");
}

// Every record's calibrated camera reads its own pipeline, and the pipelines are distinct.
void expect_wired(const StationParts& p) {
  for (std::size_t i = 0; i < p.cameras.size(); ++i) {
    const StationCamera& c = p.cameras[i];
    ASSERT_NE(c.pipeline, nullptr) << c.name;
    EXPECT_EQ(c.calibrated.source, c.pipeline.get()) << c.name;
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(p.cameras[j].pipeline.get(), c.pipeline.get());
  }
}

TEST(StationAssembly, ASceneGivesOneRecordPerCameraWithItsCalibrationAndAgeBound) {
  const sim::Scene scene = default_scene();
  ASSERT_EQ(scene.cameras.size(), 3u);
  ASSERT_TRUE(scene.effects.camera_delay);
  RunOptions o;
  o.headless = true;
  const std::unique_ptr<StationParts> p = assemble_from_scene(scene, o);
  ASSERT_EQ(p->cameras.size(), scene.cameras.size()) << p->report.missing_summary();
  expect_wired(*p);
  // The scene's camera delay (30 ms ± 5 ms) is known: three frame periods at 30 Hz (100 ms)
  // plus mean + 3 sigma.
  const double delay_s =
      1e-3 * (scene.effects.camera_delay->mean_ms + 3.0 * scene.effects.camera_delay->jitter_ms);
  EXPECT_NEAR(delay_s, 0.045, 1e-12);
  for (std::size_t i = 0; i < scene.cameras.size(); ++i) {
    const StationCamera& c = p->cameras[i];
    const sim::SceneCamera& sc = scene.cameras[i];
    EXPECT_EQ(c.name, "sim:" + sc.name);
    EXPECT_EQ(c.description.name, sc.name);
    EXPECT_EQ(c.device, nullptr) << "the simulation owns a scene's devices";
    EXPECT_EQ(c.link, nullptr);
    EXPECT_FALSE(c.awaited);
    EXPECT_EQ(c.calibrated.p_c.fx, sc.p_c.fx);
    EXPECT_EQ(c.calibrated.p_c.width, sc.p_c.width);
    EXPECT_EQ((c.calibrated.T_world_real.t - sc.T_world_cam.t).norm(), 0.0);
    EXPECT_EQ(c.calibrated.d_m, sc.d_m);
    EXPECT_NEAR(c.calibrated.max_video_age_s, 3.0 / sc.rate_hz + delay_s, 1e-12);
  }
  // The stereo pair is found by the cameras' scene names.
  ASSERT_TRUE(p->updater);
  ASSERT_EQ(p->updater->config().stereo_pairs.size(), 1u);
  const ModelStereoPair& pair = p->updater->config().stereo_pairs[0];
  EXPECT_EQ(p->cameras[pair.left].description.name, scene.stereo[0].left);
  EXPECT_EQ(p->cameras[pair.right].description.name, scene.stereo[0].right);
  EXPECT_EQ(p->camera_index("no such camera"), -1);
}

TEST(StationAssembly, ASceneWithCamerasFromTheNetworkGivesLinksOnConsecutivePorts) {
  RunOptions o;
  o.headless = true;
  o.cameras_from = "rtp://127.0.0.1:47310";  // built, never started: nothing binds the port
  const sim::Scene scene = default_scene();
  const std::unique_ptr<StationParts> p = assemble_from_scene(scene, o);
  ASSERT_EQ(p->cameras.size(), scene.cameras.size()) << p->report.missing_summary();
  expect_wired(*p);
  for (std::size_t i = 0; i < p->cameras.size(); ++i) {
    const StationCamera& c = p->cameras[i];
    EXPECT_EQ(c.name, "net:" + scene.cameras[i].name);
    EXPECT_EQ(c.description.id, "rtp://127.0.0.1:" + std::to_string(47310 + 2 * i));
    ASSERT_NE(c.device, nullptr);
    EXPECT_EQ(c.device->id(), c.description.id);
    EXPECT_NE(c.link, nullptr) << "a network camera has its link";
    EXPECT_TRUE(c.awaited) << "the remote site starts with the station";
    EXPECT_TRUE(c.link->view_needed()) << "full rate until the view says otherwise";
  }
}

class StationFileAssembly : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("station_assembly_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // As hybrid-calib writes it: fx 510, 640x480, centre (0.25, -0.1, 0.05).
    std::ofstream(dir_ / "cam.yaml")
        << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
           "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
           "   data: [ 510., 0., 318., 0., 505., 242., 0., 0., 1. ]\n"
           "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
           "   data: [ 0., 0., 0., 0., 0. ]\n"
           "camera_pose_R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
           "   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n"
           "camera_pose_t: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n"
           "   data: [ 0.25, -0.1, 0.05 ]\n";
    std::ofstream(dir_ / "station.yaml")
        << "cameras:\n"
           "  - {name: left, id: 'mock:640x480', calibration: cam.yaml, d_m: 1.25,"
           " max_video_age_ms: 80}\n"
           "  - {name: far, id: 'rtp://127.0.0.1:47320', calibration: cam.yaml, d_m: 2}\n"
           "  - {name: small, id: 'mock:320x240', calibration: cam.yaml, d_m: 1, optional: true}\n"
           "tracker: {id: mock}\n"
           "workspace: {min_m: [-1, -0.5, 0.5], max_m: [1, 0.5, 2]}\n";
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path dir_;
};

TEST_F(StationFileAssembly, GivesTheSameRecordsAndRefusesACameraThatCannotDeliverItsSize) {
  const StationConfig config = load_station_config((dir_ / "station.yaml").string());
  RunOptions o;
  o.headless = true;
  const std::unique_ptr<StationParts> p = assemble_from_config(config, o);
  EXPECT_FALSE(p->report.fatal()) << p->report.missing_summary();
  ASSERT_EQ(p->cameras.size(), 2u) << "the 320x240 camera calibrated at 640x480 is refused";
  expect_wired(*p);
  // The refused camera is in the report, skipped (optional), naming both sizes.
  int skipped = 0;
  for (const DeviceLine& d : p->report.devices())
    if (d.id.find("small") != std::string::npos) {
      ++skipped;
      EXPECT_EQ(d.status, DeviceStatus::kSkipped);
      EXPECT_NE(d.detail.find("640x480"), std::string::npos) << d.detail;
      EXPECT_NE(d.detail.find("320x240"), std::string::npos) << d.detail;
    }
  EXPECT_EQ(skipped, 1);

  const StationCamera& left = p->cameras[0];
  EXPECT_EQ(left.name, "left");
  ASSERT_NE(left.device, nullptr);
  EXPECT_EQ(left.link, nullptr) << "a camera on this host has no link";
  EXPECT_EQ(left.calibrated.p_c.fx, 510.0);
  EXPECT_EQ(left.calibrated.p_c.width, 640);
  EXPECT_NEAR((left.calibrated.T_world_real.t - Eigen::Vector3d(0.25, -0.1, 0.05)).norm(), 0.0,
              1e-12);
  EXPECT_EQ(left.calibrated.d_m, 1.25);
  EXPECT_DOUBLE_EQ(left.calibrated.max_video_age_s, 0.080);
  EXPECT_EQ(left.description.calibration_file, (dir_ / "cam.yaml").string());

  const StationCamera& far = p->cameras[1];
  EXPECT_EQ(far.name, "far");
  EXPECT_NE(far.link, nullptr) << "the rtp:// camera has its link";
  EXPECT_FALSE(far.awaited) << "station.yaml's cameras are not waited for";
  // A stream's rate is unknown at the start: the default bound's 100 ms.
  EXPECT_DOUBLE_EQ(far.calibrated.max_video_age_s, core::default_max_video_age_s(0.0));
  EXPECT_DOUBLE_EQ(far.calibrated.max_video_age_s, 0.100);
  EXPECT_EQ(p->camera_index("far"), 1);
}

}  // namespace
}  // namespace hd::station
