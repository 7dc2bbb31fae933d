// hybrid-remote --scene scenes/default.yaml streaming to the station's network camera on
// loopback: frames arrive at the scene camera's size, stamped on every packet with the capture
// time (ntp-64) and the camera's state, and the capture time maps to before the arrival.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/sender/rtp_send_pipeline.h"
#include "test_paths.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

TEST(RemoteStream, TheSimulatedCamerasArriveStampedWithCaptureTimeAndCameraState) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  // Camera 1 of the default scene goes to port + 2: listen there, as the station would.
  RtpReceiveConfig c;
  c.listen = {"127.0.0.1", static_cast<uint16_t>(port + 2)};
  RtpCamera cam(c);
  cam.negotiate({640, 480, {}, 0.0});  // scenes/default.yaml: both cameras 640x480
  cam.start();
  const int64_t before_ns = monotonic_now_ns();
  testing::ChildProcess remote({hd::test::remote_bin(), "--scene",
                                std::string(hd::test::source_dir()) + "/scenes/default.yaml",
                                "--to", "rtp://127.0.0.1:" + std::to_string(port)});
  ASSERT_TRUE(eventually([&] { return cam.stats().stamped_frames >= 10; }))
      << cam.stats().packets << " packets, " << cam.stats().unstamped_frames << " unstamped";
  ASSERT_TRUE(cam.frames().fetch());
  const int64_t fetched_ns = monotonic_now_ns();
  const Frame& f = cam.frames().latest();
  EXPECT_EQ(f.width, 640);
  EXPECT_EQ(f.height, 480);
  EXPECT_TRUE(f.device_time_trusted);
  // Captured after the sender was started, before it could be fetched.
  EXPECT_GT(f.host_timestamp_ns, before_ns);
  EXPECT_LT(f.host_timestamp_ns, fetched_ns);
  const RtpCameraStats s = cam.stats();
  EXPECT_EQ(s.unstamped_frames, 0u);
  EXPECT_EQ(s.capture_after_arrival, 0u);  // one host: the mapped capture precedes the arrival
  for (uint64_t e : s.stamp_errors) EXPECT_EQ(e, 0u);
  EXPECT_EQ(s.malformed_total, 0u);
  EXPECT_EQ(s.last_camera_index, 1);
  EXPECT_EQ(s.last_calibration_revision, 1);
  // RTCP both ways: the sender's reports arrived, and the station's feedback has a destination.
  EXPECT_TRUE(eventually([&] { return cam.feedback().rtcp_received_from_sender > 0; }));
  EXPECT_GE(cam.stats().feedback_targets, 1u);
}

TEST(RemoteStream, TheSendPipelineIsDescribedFromItsSettings) {
  remote::RtpSendConfig c;
  c.width_px = 1280;
  c.height_px = 720;
  c.rate_hz = 60;
  c.key_interval_s = 0.5;
  EXPECT_EQ(c.key_int_frames(), 30);
  EXPECT_EQ(c.vbv_buffer_ms(), 17);  // one 16.7 ms frame, rounded up
  const std::string d = remote::send_pipeline_description(c);
  for (const char* part : {"tune=zerolatency", "speed-preset=ultrafast", "bframes=0",
                           "key-int-max=30", "vbv-buf-capacity=17", "config-interval=-1",
                           "width=1280,height=720,framerate=60000/1000", "port=5600", "port=5601"})
    EXPECT_NE(d.find(part), std::string::npos) << part << " in " << d;
}

}  // namespace
}  // namespace hd::drivers
