// The sender-clock offset measured over the real link: an RtpSender whose clock runs 2.5 s ahead
// of this host's (its test_clock_shift_ns: ntp-64 capture times, RTCP sender reports and round
// trips alike, as a sender at another site would be) streams to an RtpCamera on loopback. Once
// the mapping is measured, the offset is within its reported uncertainty of the truth (closed
// form: this host's realtime - monotonic plus the shift), every frame's mapped capture time is
// within it of the time the test captured that frame (the frame number is painted into the
// image), no capture time is after its arrival, and on loopback the uncertainty is small.
#include <gtest/gtest.h>

#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gst_launch_sender.h"
#include "drivers/rtp/rtp_camera.h"
#include "remote/sender/rtp_sender.h"
#include "test_wait.h"

namespace hd::drivers {
namespace {

constexpr int kWidth = 320, kHeight = 240, kBits = 16, kStripePx = kWidth / kBits;
constexpr int64_t kShiftNs = 2'500'000'000LL;
// The sender report's NTP time comes from g_get_real_time (microseconds): the estimate may be off
// by that truncation on top of its uncertainty.
constexpr int64_t kResolutionNs = 2'000;

using drivers::realtime_minus_monotonic_ns;

// Frame number n as kBits white/black stripes (H.264 keeps stripes this wide intact).
void paint(Frame& f, uint32_t n) {
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const uint8_t v = (n >> (x / kStripePx)) & 1u ? 255 : 0;
      uint8_t* p = f.data.data() + std::size_t(y) * f.stride_bytes + std::size_t(x) * 4;
      p[0] = p[1] = p[2] = v;
      p[3] = 255;
    }
}

uint32_t read_number(const Frame& f) {
  uint32_t n = 0;
  for (int b = 0; b < kBits; ++b) {
    const uint8_t* p = f.data.data() + std::size_t(f.height / 2) * f.stride_bytes +
                       std::size_t(b * kStripePx + kStripePx / 2) * 4;
    if (p[1] > 128) n |= 1u << b;
  }
  return n;
}

TEST(RemoteClock, AShiftedSenderClockIsMeasuredAndFramesMapWithinTheReportedUncertainty) {
  const uint16_t port = testing::free_rtp_port();
  ASSERT_NE(port, 0);
  RtpReceiveConfig rc;
  rc.listen = {"127.0.0.1", port};
  rc.rtcp_interval_ms = 200;  // many samples quickly
  RtpCamera cam(rc);
  cam.negotiate({kWidth, kHeight, {}, 0.0});
  cam.start();
  remote::RtpSendConfig sc;
  sc.port = port;
  sc.width_px = kWidth;
  sc.height_px = kHeight;
  sc.rate_hz = 30.0;
  sc.bitrate_kbps = 1500;
  sc.rtcp_interval_ms = 200;
  sc.test_clock_shift_ns = kShiftNs;
  remote::RtpSender sender(sc);
  sender.start();

  std::vector<std::atomic<int64_t>> truth(1u << kBits);  // capture time by frame number
  std::atomic<bool> stop{false};
  std::thread feeder([&] {
    Frame f;
    f.allocate_rgba(kWidth, kHeight);
    auto next = std::chrono::steady_clock::now();
    for (uint32_t n = 1; !stop && n < truth.size(); ++n) {
      paint(f, n);
      f.host_timestamp_ns = monotonic_now_ns();
      truth[n].store(f.host_timestamp_ns);
      sender.push(f);
      next += std::chrono::milliseconds(33);
      std::this_thread::sleep_until(next);  // the camera's frame rate, not a synchronisation
    }
  });

  // Measured, with a full window of sender reports and round trips.
  ASSERT_TRUE(eventually([&] {
    const ClockMapping m = cam.clock_mapping();
    return m.kind == ClockMapping::Kind::kMeasured &&
           m.samples >= 2 * ClockOffsetEstimator::kWindow;
  }));
  const ClockMapping m = cam.clock_mapping();
  const int64_t true_offset = -(realtime_minus_monotonic_ns() + kShiftNs);
  std::printf("offset error %.3f ms, uncertainty %.3f ms, round trip %.3f ms, %llu samples\n",
              double(m.offset_ns - true_offset) * 1e-6, double(m.uncertainty_ns) * 1e-6,
              double(m.round_trip_ns) * 1e-6, static_cast<unsigned long long>(m.samples));
  EXPECT_LE(std::llabs(m.offset_ns - true_offset), m.uncertainty_ns + kResolutionNs);
  EXPECT_LT(m.uncertainty_ns, 5'000'000);  // loopback: a few ms at most
  EXPECT_GT(sender.stats().round_trips, 0u);

  // Frames from now on: mapped with the measured offset, each within its uncertainty.
  RtpFrameTiming t;
  while (cam.pop_timing(t)) {
  }
  std::map<uint64_t, RtpFrameTiming> timings;  // by the camera's sequence
  int checked = 0;
  int64_t worst_ns = 0;
  ASSERT_TRUE(eventually([&] {
    while (cam.pop_timing(t)) timings[t.sequence] = t;
    if (!cam.frames().fetch()) return checked >= 30;
    const Frame& f = cam.frames().latest();
    const uint32_t n = read_number(f);
    const auto it = timings.find(f.sequence);
    if (it == timings.end() || n == 0 || n >= truth.size()) return false;
    const RtpFrameTiming& ft = it->second;
    EXPECT_TRUE(ft.stamped);
    EXPECT_EQ(f.host_timestamp_ns, ft.capture_ns);
    EXPECT_LE(ft.capture_ns, ft.arrival_ns);  // never captured after it arrived
    const int64_t error = f.host_timestamp_ns - truth[n].load();
    EXPECT_LE(std::llabs(error), ft.clock_uncertainty_ns + kResolutionNs)
        << "frame " << n << " uncertainty " << ft.clock_uncertainty_ns << " error " << error
        << " arrival-truth " << ft.arrival_ns - truth[n].load();
    // The sender's stages lie between capture and arrival, in order.
    EXPECT_LT(ft.capture_ns, ft.encoded_ns);  // encoding takes time
    EXPECT_LE(ft.encoded_ns, ft.sent_ns);
    EXPECT_LE(ft.decoded_ns, ft.published_ns);
    EXPECT_LE(ft.sent_ns, ft.received_ns + ft.clock_uncertainty_ns + kResolutionNs);
    // udpsrc's arrival stamp, then out of the jitter buffer, then decoded: all read on this
    // host's CLOCK_MONOTONIC as they happen (the arrival was once the jitter buffer's smoothed
    // PTS, which under load lay after the decode).
    EXPECT_LE(ft.arrival_ns, ft.received_ns);
    EXPECT_LE(ft.received_ns, ft.decoded_ns);
    worst_ns = std::max<int64_t>(worst_ns, std::llabs(error));
    return ++checked >= 30;
  }));
  std::printf("%d frames checked, worst capture-time error %.3f ms\n", checked, worst_ns * 1e-6);
  stop = true;
  feeder.join();
  sender.stop();
  cam.stop();
}

}  // namespace
}  // namespace hd::drivers
