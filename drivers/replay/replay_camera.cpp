// The replay camera: recorded pictures published as RGBA8 frames on a rate grid, waiting for the
// consumer rather than overwriting (see replay_camera.h).
#include "drivers/replay/replay_camera.h"

#include <chrono>
#include <cmath>

#include "drivers/clock/monotonic_clock.h"

namespace hd::drivers {

namespace {

constexpr double kMaxRateHz = 1000.0;
// How often the player looks again while it waits for an exposure time or for the consumer; short
// enough that stop() and a fast consumer are not kept waiting.
constexpr auto kPoll = std::chrono::milliseconds(1);

}  // namespace

ReplayCamera::ReplayCamera(ReplayCameraConfig config) : config_(std::move(config)) {}

ReplayCamera::~ReplayCamera() {
  stop();
}

void ReplayCamera::open() {
  if (!(config_.rate_hz > 0 && config_.rate_hz <= kMaxRateHz))
    throw DeviceError("replay camera " + config_.id + ": rate " + std::to_string(config_.rate_hz) +
                      " Hz outside (0, 1000]");
  if (!config_.load) throw DeviceError("replay camera " + config_.id + ": no pictures to play");
  std::vector<ReplayImage> images;
  try {
    images = config_.load();
  } catch (const std::exception& e) {
    throw DeviceError("replay camera " + config_.id + ": " + e.what());
  }
  if (images.empty()) throw DeviceError("replay camera " + config_.id + ": no pictures to play");
  for (const ReplayImage& im : images) {
    const bool well_formed =
        im.width > 0 && im.height > 0 &&
        im.gray.size() == static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height);
    if (!well_formed)
      throw DeviceError("replay camera " + config_.id + ": picture " + im.name +
                        ": its pixels do not match its size " + size_text(im.width, im.height));
    if (im.width != images.front().width || im.height != images.front().height)
      throw DeviceError("replay camera " + config_.id + ": picture " + im.name + " is " +
                        size_text(im.width, im.height) + " but " + images.front().name + " is " +
                        size_text(images.front().width, images.front().height) +
                        "; a camera has one size");
  }
  images_ = std::move(images);
}

CameraFormat ReplayCamera::format() const {
  if (images_.empty()) return {};
  return {images_.front().width, images_.front().height, PixelFormat::kRgba8, config_.rate_hz};
}

void ReplayCamera::start() {
  if (running_) return;
  if (images_.empty()) open();
  const int64_t epoch = config_.epoch_ns ? config_.epoch_ns() : monotonic_now_ns();
  ended_ = false;
  running_ = true;
  thread_ = std::thread([this, epoch] { run(epoch); });
}

void ReplayCamera::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
}

SourceState ReplayCamera::state() const {
  if (!running_.load(std::memory_order_acquire) || ended_.load(std::memory_order_acquire))
    return SourceState::kClosed;
  return SourceState::kStreaming;
}

void ReplayCamera::run(int64_t epoch_ns) {
  const auto period_ns = static_cast<int64_t>(std::llround(1e9 / config_.rate_hz));
  for (std::size_t k = 0; k < images_.size(); ++k) {
    const int64_t exposure_ns = epoch_ns + config_.offset_ns + static_cast<int64_t>(k) * period_ns;
    // Not before its time, and never over a frame the consumer has not taken yet.
    while (running_.load(std::memory_order_relaxed) &&
           (monotonic_now_ns() < exposure_ns || !frames_.taken()))
      std::this_thread::sleep_for(kPoll);
    if (!running_.load(std::memory_order_relaxed)) return;
    const ReplayImage& im = images_[k];
    Frame& f = frames_.write_slot();
    if (f.width != im.width || f.height != im.height || f.format != PixelFormat::kRgba8)
      f.allocate_rgba(im.width, im.height);  // once per mailbox slot
    for (std::size_t i = 0; i < im.gray.size(); ++i) {
      uint8_t* px = f.data.data() + 4 * i;
      px[0] = px[1] = px[2] = im.gray[i];
      px[3] = 255;
    }
    f.sequence = k;
    f.device_timestamp_ns = exposure_ns;  // the player is the device: its clock is the host's
    f.host_timestamp_ns = exposure_ns;
    f.device_time_trusted = true;
    frames_.publish();
  }
  ended_.store(true, std::memory_order_release);
}

}  // namespace hd::drivers
