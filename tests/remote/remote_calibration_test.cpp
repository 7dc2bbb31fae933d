// p_c and P_c in the stream: RtpSender puts the calibration element on the last packet of every
// frame, the station's RtpCamera hands each frame over with the calibration of its revision, and
// a new calibration (a camera that moved) reaches the frames that follow it.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "core/opencv_pixels.h"
#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/sender/rtp_sender.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

core::Pinhole example_p_c() {
  core::OpenCvIntrinsics k;
  k.fx = 301.25;
  k.fy = 300.5;
  k.cx = 159.75;
  k.cy = 118.25;
  k.width = 320;
  k.height = 240;
  k.distortion = {-0.21, 0.043, 0.0011, -0.0007, 0.013};
  k.distortion_count = 5;
  return core::from_opencv(k);
}

// Draws a frame every 1/30 s into the sender (the camera), until stopped.
class FrameSource {
 public:
  explicit FrameSource(remote::RtpSender& s) : sender_(s) {
    frame_.allocate_rgba(320, 240);
    thread_ = std::thread([this] {
      while (!stop_) {
        frame_.host_timestamp_ns = monotonic_now_ns();
        frame_.data[(frame_.sequence++ * 4) % frame_.data.size()] ^= 0xFF;
        sender_.push(frame_);
        std::this_thread::sleep_for(std::chrono::milliseconds(33));  // the camera's rate
      }
    });
  }
  ~FrameSource() {
    stop_ = true;
    thread_.join();
  }

 private:
  remote::RtpSender& sender_;
  Frame frame_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(RemoteCalibration, EveryFrameArrivesWithTheSendersCalibrationAndANewOneFollows) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig rc;
  rc.listen = {"127.0.0.1", port};
  RtpCamera cam(rc);
  cam.open();  // no size: learnt from the stream
  cam.start();

  remote::RtpSendConfig sc;
  sc.port = port;
  sc.width_px = 320;
  sc.height_px = 240;
  sc.rate_hz = 30;
  sc.camera_index = 4;
  sc.calibration_revision = 7;
  sc.p_c = example_p_c();
  sc.T_world_cam.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1, 0.1).normalized()).matrix();
  sc.T_world_cam.t = {0.1, -0.35, 1.2};
  remote::RtpSender sender(sc);
  sender.start();
  FrameSource source(sender);

  Frame got;
  ASSERT_TRUE(eventually([&] {
    if (!cam.frames().fetch()) return false;
    got = cam.frames().latest();
    return got.calibration.present;
  })) << cam.stats().packets
      << " packets, " << cam.stats().frames_published << " frames";
  EXPECT_EQ(got.calibration.revision, 7u);
  const core::Pinhole& p = got.calibration.p_c;
  // Doubles on the wire: the values are the sender's, bit for bit (cx, cy through OpenCV's -0.5).
  EXPECT_EQ(p.width, 320);
  EXPECT_EQ(p.height, 240);
  EXPECT_EQ(p.fx, sc.p_c->fx);
  EXPECT_EQ(p.fy, sc.p_c->fy);
  EXPECT_EQ(p.cx, sc.p_c->cx);
  EXPECT_EQ(p.cy, sc.p_c->cy);
  EXPECT_EQ(p.distortion_count, 5);
  EXPECT_EQ(p.distortion, sc.p_c->distortion);
  EXPECT_EQ(got.calibration.T_world_cam.R, sc.T_world_cam.R);
  EXPECT_EQ(got.calibration.T_world_cam.t, sc.T_world_cam.t);

  // The camera moves: a new revision with the new pose reaches the frames after it.
  core::Pose moved = sc.T_world_cam;
  moved.t.x() += 0.05;
  ASSERT_TRUE(sender.set_calibration(*sc.p_c, moved));
  EXPECT_EQ(sender.calibration_revision(), 8u);
  ASSERT_TRUE(eventually([&] {
    if (!cam.frames().fetch()) return false;
    got = cam.frames().latest();
    return got.calibration.present && got.calibration.revision == 8;
  }));
  EXPECT_EQ(got.calibration.T_world_cam.t, moved.t);
  // Once the new revision is shown, no frame of the old one follows.
  ASSERT_TRUE(eventually([&] { return cam.frames().fetch(); }));
  EXPECT_EQ(cam.frames().latest().calibration.revision, 8u);

  const RtpCameraStats s = cam.stats();
  EXPECT_EQ(s.calibration_errors_total, 0u);
  EXPECT_EQ(s.calibration_size_mismatch, 0u);
  EXPECT_GT(s.calibrations_received, 0u);
  EXPECT_EQ(s.frames_with_calibration, s.frames_published);
  ASSERT_TRUE(s.calibration);
  EXPECT_EQ(s.calibration->camera_index, 4);
  EXPECT_EQ(s.last_camera_index, 4);
  // Marker packets only: as many as frames sent, not every packet.
  const remote::RtpSenderStats st = sender.stats();
  EXPECT_GT(st.packets_with_calibration, 0u);
  EXPECT_LE(st.packets_with_calibration, st.frames_pushed);
  EXPECT_LT(st.packets_with_calibration, st.packets_stamped);
}

TEST(RemoteCalibration, ASenderRefusesACalibrationItCannotSend) {
  remote::RtpSendConfig sc;
  sc.width_px = 320;
  sc.height_px = 240;
  sc.p_c = example_p_c();
  sc.p_c->distortion_count = 6;
  EXPECT_THROW(remote::RtpSender{sc}, std::invalid_argument);
}

}  // namespace
}  // namespace hd::drivers
