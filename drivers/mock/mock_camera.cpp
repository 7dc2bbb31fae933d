#include "drivers/mock/mock_camera.h"

#include <chrono>
#include <cmath>

#include "drivers/clock/monotonic_clock.h"

namespace hd::drivers {
namespace {

Frame prototype(const MockCameraConfig& c) {
  Frame f;
  if (c.width > 0 && c.height > 0 && c.width <= 16384 && c.height <= 16384)
    f.allocate_rgba(c.width, c.height);
  return f;
}

// Sleeps until `deadline_ns`, waking regularly so stop() is never delayed by a long stall.
void sleep_until(int64_t deadline_ns, const std::atomic<bool>& running) {
  for (;;) {
    const int64_t left = deadline_ns - monotonic_now_ns();
    if (left <= 0 || !running.load(std::memory_order_relaxed)) return;
    std::this_thread::sleep_for(std::chrono::nanoseconds(std::min<int64_t>(left, 10'000'000)));
  }
}

}  // namespace

void write_test_pattern(Frame& f, uint64_t seq) {
  if (f.width <= 0 || f.height <= 0) return;
  for (int y = 0; y < f.height; ++y) {
    uint8_t* row = f.data.data() + static_cast<std::size_t>(y) * f.stride_bytes;
    for (int x = 0; x < f.width; ++x) {
      row[4 * x + 0] = static_cast<uint8_t>(x * 255 / std::max(f.width - 1, 1));
      row[4 * x + 1] = static_cast<uint8_t>(y * 255 / std::max(f.height - 1, 1));
      row[4 * x + 2] = static_cast<uint8_t>((seq * 7 + static_cast<uint64_t>(x + y)) & 0xFF);
      row[4 * x + 3] = 255;
    }
  }
  if (f.data.size() >= 8)
    for (int i = 0; i < 8; ++i)
      f.data[static_cast<std::size_t>(i)] = static_cast<uint8_t>(seq >> (8 * i));
}

uint64_t read_test_pattern_sequence(const Frame& f) {
  if (f.data.size() < 8) return UINT64_MAX;
  uint64_t seq = 0;
  for (int i = 7; i >= 0; --i) seq = (seq << 8) | f.data[static_cast<std::size_t>(i)];
  return seq;
}

MockCamera::MockCamera(MockCameraConfig config)
    : config_(std::move(config)), frames_(prototype(config_)) {}

MockCamera::~MockCamera() {
  stop();
}

void MockCamera::open() {
  if (config_.width <= 0 || config_.height <= 0 || config_.width > 16384 || config_.height > 16384)
    throw DeviceError("mock camera '" + config_.id + "': size " + std::to_string(config_.width) +
                      "x" + std::to_string(config_.height) + " outside 1..16384");
  if (!(config_.rate_hz > 0 && config_.rate_hz <= 10'000))
    throw DeviceError("mock camera '" + config_.id + "': rate_hz " +
                      std::to_string(config_.rate_hz) + " outside (0, 10000]");
  opened_ = true;
}

FormatNegotiation MockCamera::negotiate(const CameraFormatRequest& wanted) {
  open();
  FormatNegotiation n{format(), "", "", ""};
  if (wanted.width_px > 0 && wanted.height_px > 0 &&
      (wanted.width_px != config_.width || wanted.height_px != config_.height))
    n.limits = "only its configured size " + size_text(config_.width, config_.height);
  return n;
}

void MockCamera::start() {
  if (running_) return;
  if (!opened_) open();
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void MockCamera::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
}

SourceState MockCamera::state() const {
  if (!running_) return SourceState::kClosed;
  const int64_t last = last_publish_ns_.load(std::memory_order_acquire);
  if (last != 0 && monotonic_now_ns() - last > config_.stall_timeout_ns)
    return SourceState::kStalled;
  return SourceState::kStreaming;
}

void MockCamera::run() {
  const auto period_ns = static_cast<int64_t>(std::llround(1e9 / config_.rate_hz));
  int64_t shift_ns = 0;  // accumulated stall time pushes every later frame back
  int64_t start_ns = monotonic_now_ns();
  if (config_.epoch_ns) {
    // Join the shared clock's grid at its first slot not in the past.
    const int64_t epoch = config_.epoch_ns();
    const int64_t behind = start_ns - epoch;
    start_ns = behind <= 0 ? epoch : epoch + (behind + period_ns - 1) / period_ns * period_ns;
  }
  // When frame `seq` is exposed and due; each frame's slot is worked out once, as the next one
  // while the frame before it is made (the overrun check needs it then).
  struct Slot {
    int64_t exposure_ns, due_ns;
  };
  const auto slot_of = [&](uint64_t seq) {
    for (const MockStall& s : config_.stalls)
      if (s.before_sequence == seq) shift_ns += s.duration_ns;
    const int64_t exposure = start_ns + shift_ns + static_cast<int64_t>(seq) * period_ns;
    const int64_t delay =
        config_.delivery_delay_ns + (config_.extra_delay_ns ? config_.extra_delay_ns(seq) : 0);
    return Slot{exposure, exposure + delay};
  };
  Slot next = slot_of(0);
  for (uint64_t seq = 0; running_.load(std::memory_order_relaxed); ++seq) {
    const Slot slot = next;
    next = slot_of(seq + 1);
    // A scripted drop is the sensor's own and is checked first: were a late slot counted as an
    // overrun instead, the script's drops would depend on the machine's load.
    if (config_.drop_sequences.count(seq) != 0 || (config_.drop && config_.drop(seq))) {
      sleep_until(slot.due_ns, running_);
      if (!running_.load(std::memory_order_relaxed)) break;
      dropped_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    if (config_.drop_on_overrun && monotonic_now_ns() >= next.due_ns) {
      overruns_.fetch_add(1, std::memory_order_relaxed);
      dropped_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    // The picture is made before its delivery time (a simulation may look ahead), so the frame
    // is published at exposure + delay and not later by the time it takes to render.
    Frame& f = frames_.write_slot();
    f.sequence = seq;
    f.host_timestamp_ns = slot.exposure_ns;
    f.device_timestamp_ns = slot.exposure_ns + config_.device_clock_offset_ns;
    f.device_time_trusted = true;
    if (config_.generator) {
      config_.generator(f, seq);
    } else {
      write_test_pattern(f, seq);
    }
    sleep_until(slot.due_ns, running_);
    if (!running_.load(std::memory_order_relaxed)) break;
    frames_.publish();
    last_publish_ns_.store(monotonic_now_ns(), std::memory_order_release);
  }
}

}  // namespace hd::drivers
