// hybrid-remote --config remote.yaml: a mock camera (the station's driver ids) with its
// calibration file sent to the station's network camera on loopback; the frames arrive with the
// file's p_c and P_c from the stream, bit for bit. A bad file is refused naming the file,
// line:column, field and value.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "calib/calibration_file.h"
#include "core/config/config_error.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/app/remote_config.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::remote {
namespace {

namespace fs = std::filesystem;

std::string calibration_file() {
  return std::string(hd::test::source_dir()) +
         "/scenes/station-mock/cam1.yaml";  // 320x240, pose 0.6 m
}

TEST(RemoteConfig, AMockCameraArrivesWithItsFilesCalibrationFromTheStream) {
  const uint16_t port = drivers::testing::free_rtp_port();
  ASSERT_NE(port, 0);
  drivers::RtpReceiveConfig rc;
  rc.listen = {"127.0.0.1", port};
  drivers::RtpCamera cam(rc);
  cam.open();  // no calibration, no size: both come with the stream
  cam.start();
  const fs::path dir = fs::temp_directory_path() / ("remote_config_test_" + std::to_string(port));
  fs::create_directories(dir);
  std::ofstream(dir / "remote.yaml")
      << "encoder: x264enc\ncameras:\n  - name: side\n"
      << "    id: mock:320x240\n    calibration: " << calibration_file()
      << "\n    to: rtp://127.0.0.1:" << port << "\n    rate_hz: 30\n    bitrate_kbps: 800\n";
  drivers::testing::ChildProcess remote(
      {hd::test::remote_bin(), "--config", (dir / "remote.yaml").string()});
  drivers::Frame got;
  ASSERT_TRUE(eventually([&] {
    if (!cam.frames().fetch()) return false;
    got = cam.frames().latest();
    return got.calibration.present;
  })) << cam.stats().packets
      << " packets, " << cam.stats().frames_published << " frames";
  const calib::CalibrationFile file = calib::read_calibration_file(calibration_file());
  ASSERT_TRUE(file.camera_pose);
  EXPECT_EQ(got.width, 320);
  EXPECT_EQ(got.height, 240);
  EXPECT_EQ(got.calibration.revision, 1u);
  const core::Pinhole& p = got.calibration.p_c;
  // Doubles on the wire: equal to the file's values (cx, cy through OpenCV's -0.5 and back).
  EXPECT_EQ(p.width, file.pinhole.width);
  EXPECT_EQ(p.height, file.pinhole.height);
  EXPECT_EQ(p.fx, file.pinhole.fx);
  EXPECT_EQ(p.fy, file.pinhole.fy);
  EXPECT_NEAR(p.cx, file.pinhole.cx, 1e-12);
  EXPECT_NEAR(p.cy, file.pinhole.cy, 1e-12);
  EXPECT_EQ(p.distortion_count, file.pinhole.distortion_count);
  EXPECT_EQ(p.distortion, file.pinhole.distortion);
  EXPECT_EQ(got.calibration.T_world_cam.R, file.camera_pose->R);
  EXPECT_EQ(got.calibration.T_world_cam.t, file.camera_pose->t);
  EXPECT_TRUE(got.device_time_trusted);  // the capture time came too
  const drivers::RtpCameraStats s = cam.stats();
  EXPECT_EQ(s.calibration_errors_total, 0u);
  EXPECT_EQ(s.last_camera_index, 0);
  fs::remove_all(dir);
}

// The ConfigError of `text` as remote.yaml (expected to be refused).
config::ConfigError refusal(const std::string& text) {
  try {
    parse_remote_config(text, std::string(hd::test::source_dir()) + "/remote/test.yaml");
  } catch (const config::ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return config::ConfigError("", 0, 0, "", "");
}

TEST(RemoteConfig, ABadFileIsRefusedNamingFileLineColumnFieldAndValue) {
  const std::string cam = "../scenes/station-mock/cam0.yaml";
  const config::ConfigError port = refusal("cameras:\n  - id: mock\n    calibration: " + cam +
                                           "\n    to: rtp://127.0.0.1:5601\n");
  EXPECT_EQ(port.line(), 4);
  EXPECT_EQ(port.column(), 9);
  EXPECT_EQ(port.field(), "cameras[0].to");
  EXPECT_NE(port.why().find("rtp://127.0.0.1:5601"), std::string::npos) << port.what();
  EXPECT_NE(std::string(port.what()).find("remote/test.yaml:4:9"), std::string::npos)
      << port.what();

  const config::ConfigError twice = refusal("cameras:\n  - {id: mock, calibration: " + cam +
                                            ", to: 'rtp://127.0.0.1:5600'}\n"
                                            "  - {id: 'mock:320x240', calibration: " +
                                            cam + ", to: 'rtp://127.0.0.1:5600'}\n");
  EXPECT_EQ(twice.line(), 3);
  EXPECT_NE(twice.why().find("destination too"), std::string::npos) << twice.what();

  const config::ConfigError rate = refusal("cameras:\n  - id: mock\n    calibration: " + cam +
                                           "\n    to: rtp://127.0.0.1:5600\n    rate_hz: 0\n");
  EXPECT_EQ(rate.field(), "cameras[0].rate_hz");
  EXPECT_EQ(rate.line(), 5);

  const config::ConfigError missing = refusal(
      "cameras:\n  - id: mock\n    calibration: nothere.yaml"
      "\n    to: rtp://127.0.0.1:5600\n");
  EXPECT_EQ(missing.field(), "cameras[0].calibration");
  EXPECT_NE(missing.why().find("nothere.yaml"), std::string::npos) << missing.what();

  const config::ConfigError network = refusal(
      "cameras:\n  - id: rtp://127.0.0.1:5000\n    "
      "calibration: " +
      cam + "\n    to: rtp://h:5600\n");
  EXPECT_EQ(network.field(), "cameras[0].id");

  const config::ConfigError encoder = refusal(
      "encoder: x265enc\ncameras:\n  - id: mock\n"
      "    calibration: " +
      cam + "\n    to: rtp://h:5600\n");
  EXPECT_EQ(encoder.field(), "encoder");
  EXPECT_NE(encoder.why().find("x264enc"), std::string::npos) << encoder.what();

  const config::ConfigError typo =
      refusal("cameras:\n  - id: mock\n    calibraton: " + cam + "\n    to: rtp://h:5600\n");
  EXPECT_NE(std::string(typo.what()).find("calibration"), std::string::npos) << typo.what();
}

TEST(RemoteConfig, TheShippedExampleReads) {
  const RemoteConfig c =
      load_remote_config(std::string(hd::test::source_dir()) + "/remote/remote-example.yaml");
  ASSERT_EQ(c.cameras.size(), 2u);
  EXPECT_EQ(c.cameras[0].id, "mock");
  EXPECT_EQ(c.cameras[0].to.port, 5600);
  EXPECT_EQ(c.cameras[1].p_c.width, 320);
  EXPECT_EQ(c.cameras[1].bitrate_kbps, 1500);
  EXPECT_EQ(c.cameras[0].bitrate_kbps, 4000);
  EXPECT_EQ(c.encoder, "auto");
}

TEST(RemoteConfig, IntraRefreshIsOffByDefaultSetForAllAndPerCamera) {
  const std::string cams =
      "cameras:\n"
      "  - {id: mock, calibration: ../scenes/station-mock/cam0.yaml, to: rtp://127.0.0.1:5600}\n"
      "  - {id: mock, calibration: ../scenes/station-mock/cam1.yaml, to: rtp://127.0.0.1:5602,\n"
      "     intra_refresh: false}\n";
  const std::string file = std::string(hd::test::source_dir()) + "/remote/test.yaml";
  const RemoteConfig off = parse_remote_config(cams, file);
  EXPECT_FALSE(off.cameras[0].intra_refresh);
  const RemoteConfig on = parse_remote_config("intra_refresh: true\n" + cams, file);
  EXPECT_TRUE(on.cameras[0].intra_refresh);
  EXPECT_FALSE(on.cameras[1].intra_refresh);  // the camera's own setting
  EXPECT_NE(std::string(refusal("intra_refresh: 3\n" + cams).what()).find("intra_refresh"),
            std::string::npos);
}

TEST(RemoteConfig, TheProgramRefusesABadFileWithExitCode2) {
  const fs::path f = fs::temp_directory_path() / "remote_config_test_bad.yaml";
  std::ofstream(f) << "cameras:\n  - id: mock\n    to: nowhere\n";
  const std::string cmd =
      std::string(hd::test::remote_bin()) + " --config " + f.string() + " 2>" + f.string() + ".err";
  const int status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream err(f.string() + ".err");
  const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find(f.string() + ":"), std::string::npos) << text;
  EXPECT_NE(text.find("calibration"), std::string::npos) << text;
  fs::remove(f);
  fs::remove(f.string() + ".err");
}

}  // namespace
}  // namespace hd::remote
