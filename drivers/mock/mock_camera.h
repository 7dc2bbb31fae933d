#pragma once
// A CameraSource that serves generated frames at a set rate, with a controllable device clock
// offset, delivery delay, and scripted drops and stalls. Frames come from a callback so the
// simulator can render the scene into them; the default is a test pattern that carries its
// sequence number in the pixels.

#include <atomic>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "drivers/camera_source.h"

namespace hd::drivers {

/// Fills an RGBA8 frame (already sized) for device frame `sequence`. The frame's sequence and
/// timestamps (exposure) are already set when it is called.
using FrameGenerator = std::function<void(Frame& frame, uint64_t sequence)>;

/// Deterministic pattern: a gradient with the sequence number in the first 8 bytes.
void write_test_pattern(Frame& frame, uint64_t sequence);
/// The sequence number write_test_pattern() stored, or UINT64_MAX for a too-small frame.
uint64_t read_test_pattern_sequence(const Frame& frame);

struct MockStall {
  uint64_t before_sequence = 0;  ///< the stall happens before this frame is produced
  int64_t duration_ns = 0;
};

struct MockCameraConfig {
  std::string id = "mock-camera";
  int width = 64;
  int height = 48;
  double rate_hz = 60.0;
  FrameGenerator generator{};           ///< empty: write_test_pattern
  int64_t device_clock_offset_ns = 0;   ///< device clock = host exposure time + offset
  int64_t delivery_delay_ns = 0;        ///< published this long after exposure
  std::set<uint64_t> drop_sequences{};  ///< frames lost "on the wire": a sequence gap
  std::vector<MockStall> stalls{};
  int64_t stall_timeout_ns = 200'000'000;
  // For the simulator (render/sim): a clock shared with other devices, per-frame delays, drops.
  /// Host time of the shared t = 0: frames are exposed on the grid epoch + k / rate_hz, the first
  /// at or after start(). Empty: the grid starts at start().
  std::function<int64_t()> epoch_ns{};
  /// Extra delivery delay of frame `sequence` (added to delivery_delay_ns; e.g. jitter).
  std::function<int64_t(uint64_t sequence)> extra_delay_ns{};
  /// True: frame `sequence` is lost like those in drop_sequences.
  std::function<bool(uint64_t sequence)> drop{};
  /// A real sensor exposes on its own clock whether or not the host keeps up: when making a frame
  /// falls behind (the next frame is already due), this one is lost (an overrun, a sequence gap)
  /// rather than every later frame arriving later and later.
  bool drop_on_overrun = true;
};

class MockCamera : public CameraSource {
 public:
  explicit MockCamera(MockCameraConfig config);
  ~MockCamera() override;
  MockCamera(const MockCamera&) = delete;
  MockCamera& operator=(const MockCamera&) = delete;

  std::string id() const override { return config_.id; }
  void open() override;  ///< throws DeviceError on a bad size or rate
  void start() override;
  void stop() override;
  SourceState state() const override;
  /// Scripted drops plus overruns.
  uint64_t dropped_frames() const override { return dropped_.load(std::memory_order_relaxed); }
  /// Frames lost because the generator could not keep the rate (part of dropped_frames()).
  uint64_t overrun_frames() const { return overruns_.load(std::memory_order_relaxed); }
  Mailbox<Frame>& frames() override { return frames_; }
  /// The configured size, RGBA8 at the configured rate: a mock delivers nothing else.
  CameraFormat format() const override {
    return {config_.width, config_.height, PixelFormat::kRgba8, config_.rate_hz};
  }
  FormatNegotiation negotiate(const CameraFormatRequest& wanted) override;

 private:
  void run();
  MockCameraConfig config_;
  bool opened_ = false;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> dropped_{0};
  std::atomic<uint64_t> overruns_{0};
  std::atomic<int64_t> last_publish_ns_{0};
  std::thread thread_;
  Mailbox<Frame> frames_;
};

}  // namespace hd::drivers
