// GigeCamera against Aravis's fake GigE Vision camera on loopback (a real protocol peer).
#include "drivers/gige/gige_camera.h"

#include <arv.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/gige/gige_prober.h"
#include "fake_gige_camera.h"

namespace hd::drivers {
namespace {

using namespace std::chrono_literals;

constexpr const char* kId = "Aravis-Fake-SERIAL";

// Aravis keeps its interface list until arv_shutdown(); free it so LeakSanitizer sees our leaks
// only.
class AravisEnvironment : public ::testing::Environment {
 public:
  void TearDown() override { arv_shutdown(); }
};
const auto* const kEnv = ::testing::AddGlobalTestEnvironment(new AravisEnvironment);

GigeConfig config(PixelFormat format, int w, int h, double fps) {
  GigeConfig c;
  c.device_id = kId;
  c.pixel_format = format;
  c.roi = {0, 0, w, h};
  c.frame_rate_hz = fps;
  return c;
}

// Waits for a frame newer than `after`; the mailbox keeps the newest one only.
bool next_frame(GigeCamera& cam, uint64_t after, std::chrono::milliseconds timeout = 30000ms) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (cam.frames().fetch() && cam.frames().latest().sequence > after) return true;
    std::this_thread::sleep_for(1ms);
  }
  return false;
}

// Waits for a condition the stream thread brings about; the limit only bounds a hang.
bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds limit = 60000ms) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(2ms);
  }
  return true;
}

// Mismatching pixels of a Mono8 frame against arvfakecamera.c's fill, value = (x + y + k) % 255
// with k = the camera's frame id (see the pixel-by-pixel test below); k is read from pixel (0, 0)
// so frames after a reconnect (whose ids restarted) check too.
int fake_pattern_mismatches(const Frame& f) {
  const int k = f.data[0];
  int bad = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const auto v = static_cast<uint8_t>((x + y + k) % 255);
      const uint8_t* p = &f.data[static_cast<std::size_t>(y * f.stride_bytes + 4 * x)];
      if (p[0] != v || p[1] != v || p[2] != v || p[3] != 255) ++bad;
    }
  return bad;
}

// The station's configuration of a GigE camera (drivers/camera_factory.cpp): Mono8, and the
// camera's own region and rate until negotiate() asks for a size.
GigeConfig station_config() {
  GigeConfig c;
  c.device_id = kId;
  c.pixel_format = PixelFormat::kMono8;
  c.frame_rate_hz = 0.0;
  return c;
}

// Aravis's own description of its fake camera with the Width feature capped at `max_width`: a
// camera that comes back (after a restart) unable to take the region it streamed before.
std::string genicam_with_max_width(int max_width) {
  arv_get_n_interfaces();  // libaravis registers its resources when it is loaded
  GError* error = nullptr;
  GBytes* bytes = g_resources_lookup_data("/org/aravis/arv-fake-camera.xml",
                                          G_RESOURCE_LOOKUP_FLAGS_NONE, &error);
  if (bytes == nullptr) {
    ADD_FAILURE() << "Aravis's fake camera description: " << (error ? error->message : "?");
    g_clear_error(&error);
    return {};
  }
  gsize size = 0;
  const auto* data = static_cast<const char*>(g_bytes_get_data(bytes, &size));
  std::string xml(data, size);
  g_bytes_unref(bytes);
  const std::size_t node = xml.find("<Integer Name=\"Width\"");
  const std::string pmax = "<pMax>SensorWidth</pMax>";
  const std::size_t at = node == std::string::npos ? node : xml.find(pmax, node);
  if (at == std::string::npos || at > xml.find("</Integer>", node)) {
    ADD_FAILURE() << "no <pMax>SensorWidth</pMax> in the Width node of Aravis's fake camera";
    return {};
  }
  xml.replace(at, pmax.size(), "<Max>" + std::to_string(max_width) + "</Max>");
  const std::string path =
      (std::filesystem::temp_directory_path() / ("fake-camera-width-" + std::to_string(max_width) +
                                                 "-" + std::to_string(::getpid()) + ".xml"))
          .string();
  std::ofstream(path) << xml;
  return path;
}

TEST(GigeCameraFormat, NegotiateSetsTheRequestedSizeAndFramesHaveIt) {
  // The fake camera starts at 512x512; the station asks for a 640x480 calibration.
  testing::FakeGigeCamera fake;
  GigeCamera cam(station_config());
  const FormatNegotiation n = cam.negotiate({640, 480, {}, 0.0});
  EXPECT_EQ(n.delivered.width_px, 640);
  EXPECT_EQ(n.delivered.height_px, 480);
  EXPECT_EQ(n.delivered.pixel_format, PixelFormat::kMono8);
  EXPECT_GT(n.delivered.frame_rate_hz, 0.0);
  EXPECT_EQ(n.refused, "") << n.refused;
  EXPECT_EQ(n.limits, "1..2048 x 1..2048 px");  // arvfakecamera.h: a 2048x2048 sensor
  EXPECT_EQ(n.detail, "region at (0, 0), binning 1x1");
  EXPECT_TRUE(judge_format({640, 480, {}, 0.0}, n).ok);
  EXPECT_TRUE(cam.format().same_image(n.delivered));
  cam.start();
  uint64_t last = 0;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(next_frame(cam, last));
    const Frame& f = cam.frames().latest();
    last = f.sequence;
    ASSERT_EQ(f.width, 640);
    ASSERT_EQ(f.height, 480);
    EXPECT_EQ(fake_pattern_mismatches(f), 0) << "frame " << f.sequence;
  }
  EXPECT_EQ(cam.state(), SourceState::kStreaming);
  cam.stop();
  FormatEvent e;
  EXPECT_FALSE(cam.pop_format_event(e));
  EXPECT_EQ(cam.stats().wrong_format, 0u);
}

TEST(GigeCameraFormat, ASizeBeyondTheSensorIsRefusedAndTheAnswerSaysWhatItDelivers) {
  testing::FakeGigeCamera fake;
  const CameraFormatRequest want{4000, 3000, {}, 0.0};
  FormatNegotiation n;
  {
    GigeCamera cam(station_config());  // released at once: the camera takes one controller
    n = cam.negotiate(want);
  }
  EXPECT_EQ(n.delivered.width_px, 512);  // untouched: the fake camera's default
  EXPECT_EQ(n.delivered.height_px, 512);
  EXPECT_NE(n.refused.find("Width 4000 is outside the camera's 1..2048"), std::string::npos)
      << n.refused;
  EXPECT_NE(n.refused.find("Height 3000 is outside the camera's 1..2048"), std::string::npos)
      << n.refused;
  const FormatVerdict v = judge_format(want, n);
  EXPECT_FALSE(v.ok);
  EXPECT_NE(v.problem.find("delivers 512x512, not the requested 4000x3000"), std::string::npos)
      << v.problem;
  EXPECT_NE(v.problem.find("it can deliver 1..2048 x 1..2048 px"), std::string::npos) << v.problem;

  // open() with that region configured is an error naming both sizes.
  GigeConfig c = station_config();
  c.roi = {0, 0, 4000, 3000};
  GigeCamera strict(c);
  try {
    strict.open();
    FAIL() << "opened a camera that cannot deliver 4000x3000";
  } catch (const DeviceError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("delivers 512x512, not the configured 4000x3000"), std::string::npos) << msg;
    EXPECT_NE(msg.find(kId), std::string::npos) << msg;
  }
}

TEST(GigeCameraFormat, BinningIsSetAndReadBack) {
  // The fake camera keeps binning in a register (1..16) without changing its image size, which
  // is what a read-back can show here; the size is still negotiated separately.
  testing::FakeGigeCamera fake;
  GigeConfig c = station_config();
  c.binning_x = 2;
  c.binning_y = 4;
  GigeCamera cam(c);
  const FormatNegotiation n = cam.negotiate({320, 240, {}, 0.0});
  EXPECT_EQ(cam.binning_x(), 2);
  EXPECT_EQ(cam.binning_y(), 4);
  EXPECT_EQ(n.detail, "region at (0, 0), binning 2x4");
  EXPECT_EQ(n.refused, "");
  EXPECT_EQ(n.delivered.width_px, 320);
}

TEST(GigeCameraFormat, ReconnectWithOtherSettingsIsAMismatchUntilTheFormatIsRightAgain) {
  // A camera restarted with a description that caps Width at 256 comes back at its default
  // 512x512 and cannot be set to the 320x240 it streamed: it must leave kStreaming, say so with
  // a FormatEvent, publish nothing, and stream again once a restart lets it take 320x240.
  const std::string capped = genicam_with_max_width(256);
  ASSERT_FALSE(capped.empty());
  auto fake = std::make_unique<testing::FakeGigeCamera>();
  GigeCamera cam(station_config());
  ASSERT_TRUE(judge_format({320, 240, {}, 0.0}, cam.negotiate({320, 240, {}, 0.0})).ok);
  Mailbox<Frame>* mailbox = &cam.frames();
  cam.start();
  ASSERT_TRUE(next_frame(cam, 0));

  fake.reset();  // killed
  ASSERT_TRUE(wait_until([&] { return cam.state() == SourceState::kDisconnected; }));
  fake = std::make_unique<testing::FakeGigeCamera>("SERIAL", capped);
  const int64_t restarted_ns = monotonic_now_ns();
  ASSERT_TRUE(wait_until([&] { return cam.state() == SourceState::kFormatMismatch; }))
      << to_string(cam.state());
  const uint64_t published_at_mismatch = cam.frames().published();
  FormatEvent lost;
  ASSERT_TRUE(cam.pop_format_event(lost));
  EXPECT_EQ(lost.kind, FormatEventKind::kLost);
  EXPECT_EQ(lost.cause, FormatEventCause::kReconnect);
  EXPECT_EQ(lost.expected.width_px, 320);
  EXPECT_EQ(lost.expected.height_px, 240);
  EXPECT_EQ(lost.seen.width_px, 512);
  EXPECT_EQ(lost.seen.height_px, 512);
  EXPECT_GE(lost.time_ns, restarted_ns);
  EXPECT_LE(lost.time_ns, monotonic_now_ns());
  // It keeps asking (every 0.5 s) and keeps being refused: still unusable, nothing published.
  const uint64_t tries = cam.stats().reopen_attempts;
  ASSERT_TRUE(wait_until([&] { return cam.stats().reopen_attempts >= tries + 2; }));
  EXPECT_EQ(cam.state(), SourceState::kFormatMismatch);
  EXPECT_EQ(cam.frames().published(), published_at_mismatch);
  FormatEvent again;
  EXPECT_FALSE(cam.pop_format_event(again)) << "one event per loss, not one per try";

  fake.reset();
  fake = std::make_unique<testing::FakeGigeCamera>();  // Aravis's own description again
  ASSERT_TRUE(wait_until([&] { return cam.state() == SourceState::kStreaming; }))
      << to_string(cam.state());
  FormatEvent restored;
  ASSERT_TRUE(wait_until([&] { return cam.pop_format_event(restored); }));
  EXPECT_EQ(restored.kind, FormatEventKind::kRestored);
  EXPECT_EQ(restored.cause, FormatEventCause::kReconnect);
  EXPECT_GT(restored.time_ns, lost.time_ns);
  ASSERT_TRUE(next_frame(cam, cam.frames().latest().sequence));
  EXPECT_EQ(&cam.frames(), mailbox);
  const Frame& f = cam.frames().latest();
  EXPECT_EQ(f.width, 320);
  EXPECT_EQ(f.height, 240);
  EXPECT_EQ(fake_pattern_mismatches(f), 0);
  cam.stop();
  std::filesystem::remove(capped);
}

TEST(GigeCamera, OpensByIdAndNegotiatesSizeAndFormat) {
  testing::FakeGigeCamera fake;
  for (PixelFormat f :
       {PixelFormat::kMono8, PixelFormat::kRgb8, PixelFormat::kBayerRggb8, PixelFormat::kBayerGrbg8,
        PixelFormat::kBayerGbrg8, PixelFormat::kBayerBggr8}) {
    GigeCamera cam(config(f, 320, 240, 30));
    cam.open();
    EXPECT_EQ(cam.width_px(), 320) << to_string(f);
    EXPECT_EQ(cam.height_px(), 240) << to_string(f);
    EXPECT_EQ(cam.payload_bytes(), 320u * 240u * static_cast<unsigned>(bytes_per_pixel(f)));
    EXPECT_NEAR(cam.frame_rate_hz(), 30.0, 0.01);
    EXPECT_GT(cam.packet_size_bytes(), 576);  // negotiated: at least the GigE minimum
    EXPECT_EQ(cam.address(), "127.0.0.1");
    cam.start();
    ASSERT_TRUE(next_frame(cam, 0)) << to_string(f);
    const Frame& fr = cam.frames().latest();
    EXPECT_EQ(fr.width, 320);
    EXPECT_EQ(fr.height, 240);
    EXPECT_EQ(fr.stride_bytes, 320 * 4);
    EXPECT_EQ(fr.format, PixelFormat::kRgba8);
    ASSERT_EQ(fr.data.size(), 320u * 240u * 4u);
    bool opaque = true, varied = false;
    for (std::size_t i = 0; i < fr.data.size(); i += 4) {
      opaque = opaque && fr.data[i + 3] == 255;
      varied = varied || fr.data[i] != fr.data[0] || fr.data[i + 1] != fr.data[1];
    }
    EXPECT_TRUE(opaque) << to_string(f);
    EXPECT_TRUE(varied) << to_string(f) << ": the test pattern is not flat";
    cam.stop();
    EXPECT_EQ(cam.state(), SourceState::kClosed);
  }
}

TEST(GigeCamera, Mono8TestPatternMatchesTheFakeCameraGeneratorPixelByPixel) {
  // arvfakecamera.c's default fill: value = ((x + y + frame_id) % 255) * scale, scale =
  // 1 + gain + log10(exposure_us / 10000); at its defaults (gain 0, 10 ms) scale is 1. Block ids
  // wrap with period 65535 = 255 * 257, so the unwrapped sequence gives the same value mod 255.
  testing::FakeGigeCamera fake;
  GigeCamera cam(config(PixelFormat::kMono8, 97, 61, 50));  // odd sizes catch stride slips
  cam.start();
  uint64_t last = 0;
  for (int n = 0; n < 5; ++n) {
    ASSERT_TRUE(next_frame(cam, last));
    const Frame& f = cam.frames().latest();
    last = f.sequence;
    int mismatches = 0;
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const auto v = static_cast<uint8_t>((static_cast<uint64_t>(x + y) + f.sequence) % 255);
        const uint8_t* p = &f.data[static_cast<std::size_t>(y * f.stride_bytes + 4 * x)];
        if (p[0] != v || p[1] != v || p[2] != v || p[3] != 255) ++mismatches;
      }
    EXPECT_EQ(mismatches, 0) << "frame " << f.sequence;
  }
}

TEST(GigeCamera, FrameIdsAreContinuousAcrossThe65535To1WrapAtHighRate) {
  // The fake camera starts its block ids near 65000 "to trigger circular counter bugs sooner".
  testing::FakeGigeCamera fake;
  GigeCamera cam(config(PixelFormat::kMono8, 32, 32, 500));
  cam.start();
  std::vector<uint64_t> seq;
  const auto end = std::chrono::steady_clock::now() + 8s;
  GigeHandoffTiming t;
  while (std::chrono::steady_clock::now() < end) {
    while (cam.pop_timing(t)) seq.push_back(t.sequence);
    if (!seq.empty() && seq.back() > 65535 + 200) break;
    std::this_thread::sleep_for(2ms);
  }
  cam.stop();
  ASSERT_FALSE(seq.empty());
  ASSERT_LE(seq.front(), 65535u) << "the fake camera did not start below the wrap";
  ASSERT_GT(seq.back(), 65535u + 200u) << "never wrapped";
  for (std::size_t i = 1; i < seq.size(); ++i) ASSERT_EQ(seq[i], seq[i - 1] + 1) << "at " << i;
  EXPECT_EQ(cam.dropped_frames(), 0u);
  EXPECT_EQ(cam.stats().late_or_duplicate, 0u);
}

// Datagrams the kernel dropped on this process's UDP sockets because their receive buffers were
// full: the drops column of /proc/net/udp and udp6 summed over the sockets in /proc/self/fd (the
// GigE stream's among them, while its camera object lives); none when they cannot be read.
std::optional<uint64_t> udp_drops_of_this_process() {
  std::set<uint64_t> inodes;
  std::error_code ec;
  for (const auto& fd : std::filesystem::directory_iterator("/proc/self/fd", ec)) {
    std::error_code link_ec;
    const std::string target = std::filesystem::read_symlink(fd.path(), link_ec).string();
    if (!link_ec && target.rfind("socket:[", 0) == 0)
      inodes.insert(std::strtoull(target.c_str() + 8, nullptr, 10));
  }
  if (ec) return std::nullopt;
  uint64_t drops = 0;
  bool read_any = false;
  for (const char* table : {"/proc/net/udp", "/proc/net/udp6"}) {
    std::ifstream in(table);
    std::string line;
    if (!std::getline(in, line)) continue;  // the header
    read_any = true;
    // sl local rem st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops
    while (std::getline(in, line)) {
      std::istringstream words(line);
      std::vector<std::string> f;
      for (std::string w; words >> w;) f.push_back(w);
      if (f.size() >= 13 && inodes.count(std::strtoull(f[9].c_str(), nullptr, 10)) != 0)
        drops += std::strtoull(f[12].c_str(), nullptr, 10);
    }
  }
  if (!read_any) return std::nullopt;
  return drops;
}

// Every frame the fake camera sent at 60 fps is delivered, in order, or was lost because the
// kernel dropped its packets, and is counted. On a loaded machine the kernel can drop UDP
// datagrams on loopback when Aravis's receive thread waits for a CPU (seen: at start, before
// Aravis enlarges the stream socket's buffer when it takes its first frame): such a loss is named
// by the socket's own drop count, and every frame lost needs its datagrams there, a frame missing
// from the ids all of them. With no datagram dropped nothing may be lost: no gap in the ids, no
// bad buffer. A loss for any other reason (a buffer pool that ran dry, a camera that did not send
// all of a frame) is not excused.
TEST(GigeCamera, EveryFrameAt60FpsIsDeliveredInOrderOrCounted) {
  testing::FakeGigeCamera fake;
  GigeCamera cam(config(PixelFormat::kMono8, 640, 480, 60));
  cam.open();
  EXPECT_GE(cam.socket_buffer_bytes(), static_cast<int>(4 * cam.payload_bytes()));
  EXPECT_GE(cam.buffer_count(), 60 * 3 / 10 + 4);  // covers the 300 ms frame retention
  ASSERT_TRUE(udp_drops_of_this_process().has_value()) << "/proc/net/udp cannot be read";
  cam.start();
  uint64_t first = 0, last = 0, popped = 0, disorder = 0;
  bool any = false;
  GigeHandoffTiming t;
  const auto take = [&] {
    while (cam.pop_timing(t)) {
      if (any && t.sequence <= last) ++disorder;
      if (!any) first = t.sequence;
      any = true;
      last = t.sequence;
      ++popped;
    }
  };
  // 600 frames sent (10 s at 60 fps; the fake camera skips a period without using an id when a
  // loaded machine makes it late, so its ids count what it sent): waited for, not timed.
  constexpr uint64_t kSent = 600;
  EXPECT_TRUE(wait_until([&] {
    take();
    cam.frames().fetch();
    return any && last - first + 1 >= kSent;
  }));
  cam.stop();
  take();
  const GigeStats s = cam.stats();
  const std::optional<uint64_t> kernel_drops = udp_drops_of_this_process();  // socket still open
  ASSERT_TRUE(any);
  ASSERT_TRUE(kernel_drops.has_value());
  // Datagrams of a whole frame: its payload in packets of packet_size less the IP and UDP
  // headers (at least; GVSP's own header makes it more), with a leader and a trailer.
  const uint64_t data_per_packet = static_cast<uint64_t>(cam.packet_size_bytes()) - 28;
  const uint64_t packets_per_frame =
      (cam.payload_bytes() + data_per_packet - 1) / data_per_packet + 2;
  std::printf(
      "60 fps, %llu frame ids from the first delivered to the last: %llu delivered, %llu lost in "
      "the ids (%llu before the first frame), %llu bad buffers (%llu "
      "before the first frame, last status %d); the kernel dropped %llu datagrams (%llu a "
      "frame)\n",
      static_cast<unsigned long long>(last - first + 1),
      static_cast<unsigned long long>(s.frames_published),
      static_cast<unsigned long long>(s.id_gaps),
      static_cast<unsigned long long>(s.gaps_before_first_frame),
      static_cast<unsigned long long>(s.bad_buffers),
      static_cast<unsigned long long>(s.bad_before_first_frame), s.last_bad_status,
      static_cast<unsigned long long>(*kernel_drops),
      static_cast<unsigned long long>(packets_per_frame));
  // Lost only where the kernel dropped: each frame missing from the ids is all of its datagrams,
  // each bad buffer at least one. No datagram dropped: no gap, no bad buffer. Losses before the
  // first good frame are counted apart and left out: the camera streams while Aravis is still
  // setting up its stream socket, and a datagram that reaches no socket yet is in no socket's
  // drop count (seen under load: a first frame missing and two bad, with 166 datagrams dropped
  // where a whole frame is 226).
  const uint64_t gaps_after_first = s.id_gaps - s.gaps_before_first_frame;
  const uint64_t bad_after_first = s.bad_buffers - s.bad_before_first_frame;
  EXPECT_LE(gaps_after_first * packets_per_frame + bad_after_first, *kernel_drops)
      << gaps_after_first << " frames missing from the ids and " << bad_after_first
      << " bad buffers after the first frame (last ArvBufferStatus " << s.last_bad_status
      << "), but the kernel dropped " << *kernel_drops << " datagrams";
  if (*kernel_drops == 0) {
    EXPECT_EQ(s.id_gaps, 0u);
    EXPECT_EQ(s.bad_buffers, 0u) << "last ArvBufferStatus " << s.last_bad_status;
  }
  // Delivered in order, nothing skipped for other reasons, and every loss counted.
  EXPECT_EQ(disorder, 0u);
  EXPECT_EQ(s.malformed, 0u);
  EXPECT_EQ(s.late_or_duplicate, 0u);
  EXPECT_EQ(s.wrong_format, 0u);
  EXPECT_EQ(cam.dropped_frames(), s.bad_buffers + s.id_gaps);
  EXPECT_EQ(popped, s.frames_published) << "the timing ring overflowed: the span check is blind";
  // The ids from the first to the last delivered frame: each one delivered, a gap in the ids, or
  // a bad buffer (one before the first or after the last delivered frame is not in the span; seen
  // under load: a lost first frame, then a gap, then the first good one).
  const uint64_t span = last - first + 1;
  EXPECT_GE(span, s.frames_published + s.id_gaps - s.gaps_before_first_frame);
  EXPECT_LE(span, s.frames_published + s.id_gaps + s.bad_buffers - s.bad_before_first_frame);
}

TEST(GigeCamera, TimestampsAreOnTheMonotonicClockAndOrdered) {
  testing::FakeGigeCamera fake;
  GigeCamera cam(config(PixelFormat::kMono8, 64, 64, 100));
  cam.start();
  std::vector<GigeHandoffTiming> ts;
  uint64_t last_seq = 0;
  int64_t last_host = 0;
  for (int n = 0; n < 20; ++n) {
    ASSERT_TRUE(next_frame(cam, last_seq));
    const int64_t now = monotonic_now_ns();
    const Frame& f = cam.frames().latest();
    EXPECT_TRUE(f.device_time_trusted);
    EXPECT_LE(f.host_timestamp_ns, now);
    EXPECT_GT(f.host_timestamp_ns, now - 1'000'000'000);
    EXPECT_GT(f.host_timestamp_ns, last_host);
    last_host = f.host_timestamp_ns;
    last_seq = f.sequence;
  }
  cam.stop();
  GigeHandoffTiming t;
  int n = 0;
  while (cam.pop_timing(t)) {
    EXPECT_LE(t.arrival_ns, t.popped_ns);
    EXPECT_LE(t.popped_ns, t.published_ns);
    ++n;
  }
  EXPECT_GE(n, 20);
}

TEST(GigeCamera, KilledCameraIsReportedDisconnectedWithinOneSecond) {
  testing::FakeGigeCamera fake;
  GigeCamera cam(config(PixelFormat::kMono8, 320, 240, 30));
  cam.start();
  ASSERT_TRUE(next_frame(cam, 0));
  ASSERT_EQ(cam.state(), SourceState::kStreaming);
  fake.kill();
  const int64_t killed_ns = monotonic_now_ns();
  while (cam.state() != SourceState::kDisconnected &&
         monotonic_now_ns() - killed_ns < 3'000'000'000) {
    std::this_thread::sleep_for(5ms);
  }
  const int64_t took_ns = monotonic_now_ns() - killed_ns;
  EXPECT_EQ(cam.state(), SourceState::kDisconnected);
  EXPECT_LT(took_ns, 1'000'000'000) << "took " << took_ns / 1e6 << " ms";
  const int64_t stop_from_ns = monotonic_now_ns();
  cam.stop();  // must not hang or throw on a dead camera
  EXPECT_EQ(cam.state(), SourceState::kDisconnected);
  std::printf("disconnect reported after %.0f ms; stop() took %.0f ms\n", took_ns / 1e6,
              (monotonic_now_ns() - stop_from_ns) / 1e6);
}

TEST(GigeCamera, CameraThatComesBackIsReopenedAndTheSequenceContinues) {
  auto fake = std::make_unique<testing::FakeGigeCamera>();
  GigeCamera cam(config(PixelFormat::kMono8, 160, 120, 30));
  cam.start();
  ASSERT_TRUE(next_frame(cam, 0));
  Mailbox<Frame>* mailbox = &cam.frames();
  fake.reset();  // killed
  const int64_t killed_ns = monotonic_now_ns();
  while (cam.state() != SourceState::kDisconnected &&
         monotonic_now_ns() - killed_ns < 30'000'000'000)
    std::this_thread::sleep_for(5ms);
  ASSERT_EQ(cam.state(), SourceState::kDisconnected);
  cam.frames().fetch();
  const uint64_t before = cam.frames().latest().sequence;
  fake = std::make_unique<testing::FakeGigeCamera>();  // a new process: its ids restart
  ASSERT_TRUE(next_frame(cam, before)) << "not reopened";
  EXPECT_EQ(cam.state(), SourceState::kStreaming);
  EXPECT_EQ(&cam.frames(), mailbox) << "the consumer's mailbox must survive a reconnect";
  EXPECT_EQ(cam.stats().reconnects, 1u);
  // Frames after the reconnect follow on from the last one before it, and the image is right.
  GigeHandoffTiming t;
  std::vector<uint64_t> seq;
  while (cam.pop_timing(t)) seq.push_back(t.sequence);
  ASSERT_GE(seq.size(), 2u);
  for (std::size_t i = 1; i < seq.size(); ++i) EXPECT_EQ(seq[i], seq[i - 1] + 1) << i;
  EXPECT_EQ(cam.frames().latest().width, 160);
  cam.stop();
}

TEST(GigeCamera, SlowButLiveCameraIsStalledNotDisconnected) {
  testing::FakeGigeCamera fake;
  GigeConfig c = config(PixelFormat::kMono8, 64, 64, 1.0);  // one frame a second
  c.stall_timeout_ns = 200'000'000;
  GigeCamera cam(c);
  cam.start();
  ASSERT_TRUE(next_frame(cam, 0));
  const uint64_t first = cam.frames().latest().sequence;
  bool saw_stalled = false;
  const auto end = std::chrono::steady_clock::now() + 2500ms;
  while (std::chrono::steady_clock::now() < end) {
    saw_stalled = saw_stalled || cam.state() == SourceState::kStalled;
    ASSERT_NE(cam.state(), SourceState::kDisconnected) << "a live camera answered the probe";
    cam.frames().fetch();  // consume, so the wait below sees a frame that arrives after it
    std::this_thread::sleep_for(10ms);
  }
  EXPECT_TRUE(saw_stalled);
  EXPECT_GE(cam.stats().liveness_probes, 1u);
  ASSERT_TRUE(next_frame(cam, first));  // the next frame arrives and streaming resumes
  EXPECT_EQ(cam.state(), SourceState::kStreaming);
  cam.stop();
}

TEST(GigeCamera, StopThenStartStreamsAgain) {
  testing::FakeGigeCamera fake;
  GigeCamera cam(config(PixelFormat::kBayerRggb8, 64, 48, 60));
  cam.start();
  ASSERT_TRUE(next_frame(cam, 0));
  cam.stop();
  const uint64_t before = cam.frames().latest().sequence;
  cam.start();
  ASSERT_TRUE(next_frame(cam, before));
  cam.stop();
  EXPECT_EQ(cam.dropped_frames(), 0u);
}

TEST(GigeCamera, UnknownIdIsAnErrorNamingItAndListingWhatWasFound) {
  testing::FakeGigeCamera fake;
  GigeConfig c = config(PixelFormat::kMono8, 64, 64, 30);
  c.device_id = "Aravis-Fake-NOPE";
  GigeCamera missing(c);
  try {
    missing.open();
    FAIL() << "opened a camera that does not exist";
  } catch (const DeviceError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("Aravis-Fake-NOPE"), std::string::npos) << msg;
    EXPECT_NE(msg.find(kId), std::string::npos) << msg;
  }
}

TEST(GigeCamera, UnsupportedPixelFormatIsAnErrorNamingTheDevice) {
  GigeCamera cam(config(PixelFormat::kYuyv, 64, 64, 30));
  try {
    cam.open();
    FAIL() << "accepted YUYV";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find(kId), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("YUYV"), std::string::npos) << e.what();
  }
}

TEST(GigeProber, ListsTheFakeCameraAsOpenable) {
  testing::FakeGigeCamera fake;
  const auto devices = probe_gige_devices();
  const auto it =
      std::find_if(devices.begin(), devices.end(), [](const DeviceInfo& d) { return d.id == kId; });
  ASSERT_NE(it, devices.end());
  EXPECT_EQ(it->kind, "gige");
  EXPECT_TRUE(it->openable) << it->reason;
  EXPECT_NE(it->description.find("127.0.0.1"), std::string::npos) << it->description;
}

}  // namespace
}  // namespace hd::drivers
