// hybrid-remote --config with Aravis's fake GigE camera (a real GVCP/GVSP peer, through the
// station's GigE driver): set to its calibration's size, sent to the station's network camera on
// loopback with the file's p_c and P_c in the stream.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "calib/calibration_file.h"
#include "drivers/gige/fake_gige_camera.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::remote {
namespace {

namespace fs = std::filesystem;

TEST(RemoteGigeConfig, TheFakeGigeCameraArrivesWithItsFilesCalibrationFromTheStream) {
  drivers::testing::FakeGigeCamera fake("REMOTECFG");  // starts at 512x512
  const uint16_t port = drivers::testing::free_rtp_port();
  ASSERT_NE(port, 0);
  drivers::RtpReceiveConfig rc;
  rc.listen = {"127.0.0.1", port};
  drivers::RtpCamera cam(rc);
  cam.open();
  cam.start();
  const std::string cal =
      std::string(hd::test::source_dir()) + "/scenes/station-mock/cam0.yaml";  // 640x480
  const fs::path dir =
      fs::temp_directory_path() / ("remote_gige_config_test_" + std::to_string(port));
  fs::create_directories(dir);
  std::ofstream(dir / "remote.yaml")
      << "encoder: x264enc\ncameras:\n  - name: gige\n"
      << "    id: Aravis-Fake-REMOTECFG\n    calibration: " << cal
      << "\n    to: rtp://127.0.0.1:" << port << "\n    rate_hz: 25\n    bitrate_kbps: 1000\n";
  drivers::testing::ChildProcess remote(
      {hd::test::remote_bin(), "--config", (dir / "remote.yaml").string()});
  drivers::Frame got;
  ASSERT_TRUE(eventually([&] {
    if (!cam.frames().fetch()) return false;
    got = cam.frames().latest();
    return got.calibration.present;
  })) << cam.stats().packets
      << " packets, " << cam.stats().frames_published << " frames";
  const calib::CalibrationFile file = calib::read_calibration_file(cal);
  ASSERT_TRUE(file.camera_pose);
  // The camera was set to the calibration's size, not its own 512x512.
  EXPECT_EQ(got.width, 640);
  EXPECT_EQ(got.height, 480);
  const core::Pinhole& p = got.calibration.p_c;
  EXPECT_EQ(p.width, 640);
  EXPECT_EQ(p.fx, file.pinhole.fx);
  EXPECT_EQ(p.fy, file.pinhole.fy);
  EXPECT_NEAR(p.cx, file.pinhole.cx, 1e-12);
  EXPECT_NEAR(p.cy, file.pinhole.cy, 1e-12);
  EXPECT_EQ(p.distortion, file.pinhole.distortion);
  EXPECT_EQ(got.calibration.T_world_cam.R, file.camera_pose->R);
  EXPECT_EQ(got.calibration.T_world_cam.t, file.camera_pose->t);
  EXPECT_EQ(cam.stats().calibration_errors_total, 0u);
  remote.stop();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hd::remote
