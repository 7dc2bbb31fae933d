#include "station/video/camera_pipeline.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "drivers/clock/monotonic_clock.h"
#include "station/video/frame_copy.h"

namespace hd::station {
namespace {

drivers::Frame rgba_prototype(const core::Pinhole& p_c) {
  if (!p_c.valid())
    throw std::invalid_argument("camera pipeline: camera intrinsics are not a valid pinhole");
  drivers::Frame f;
  f.allocate_rgba(p_c.width, p_c.height);
  return f;
}

}  // namespace

CameraPipeline::CameraPipeline(drivers::CameraSource& source, CameraPipelineConfig config)
    : source_(source),
      config_(config),
      undistort_(Undistorter::needed(config.p_c)),
      undistorter_(undistort_ ? Undistorter(config.p_c) : Undistorter()),
      model_period_ns_(std::isfinite(config.model_period_s) && config.model_period_s > 0
                           ? static_cast<int64_t>(std::llround(config.model_period_s * 1e9))
                           : 0),
      frames_(rgba_prototype(config.p_c)),
      model_frames_(rgba_prototype(config.p_c)) {
  if (config_.poll_ns <= 0) config_.poll_ns = 500'000;
}

CameraPipeline::~CameraPipeline() {
  stop();
}

void CameraPipeline::open() {
  source_.open();
}

void CameraPipeline::start() {
  if (running_.load()) return;
  source_.start();
  running_.store(true);
  thread_ = std::thread([this] { run(); });
}

void CameraPipeline::stop() {
  running_.store(false);
  if (thread_.joinable()) {
    thread_.join();
    source_.stop();
  }
}

uint64_t CameraPipeline::dropped_frames() const {
  return source_.dropped_frames() + rejected_.load(std::memory_order_relaxed);
}

bool CameraPipeline::process_one() {
  drivers::Mailbox<drivers::Frame>& in = source_.frames();
  if (!in.fetch()) return false;
  const drivers::Frame& src = in.latest();
  const drivers::CameraFormat expected{config_.p_c.width, config_.p_c.height,
                                       drivers::PixelFormat::kRgba8, 0.0};
  if (!is_rgba_frame(src, expected.width_px, expected.height_px)) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    // State first: a consumer that sees the event must also see the camera as unusable.
    if (!mismatch_.exchange(true, std::memory_order_acq_rel)) {
      events_.push({drivers::monotonic_now_ns(), drivers::FormatEventKind::kLost,
                    drivers::FormatEventCause::kFrame, expected,
                    drivers::CameraFormat{src.width, src.height, src.format, 0.0}});
    }
    return true;
  }
  drivers::Frame& out = frames_.write_slot();
  const bool ok = undistort_ ? undistorter_.apply(src, out) : copy_frame(src, out);
  if (!ok) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    return true;
  }
  if (mismatch_.load(std::memory_order_relaxed)) {
    events_.push({drivers::monotonic_now_ns(), drivers::FormatEventKind::kRestored,
                  drivers::FormatEventCause::kFrame, expected, expected});
    mismatch_.store(false, std::memory_order_release);
  }
  // The model's copy is taken from the finished frame (no second undistortion) before the
  // station can see it: after publish() the slot belongs to the mailbox.
  const int64_t t_ns = out.host_timestamp_ns;
  if (!model_sent_ || model_period_ns_ == 0 || t_ns - last_model_ns_ >= model_period_ns_ ||
      t_ns < last_model_ns_) {
    copy_frame(out, model_frames_.write_slot());
    model_frames_.publish();
    model_sent_ = true;
    last_model_ns_ = t_ns;
  }
  frames_.publish();
  processed_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

void CameraPipeline::run() {
  while (running_.load(std::memory_order_acquire)) {
    if (!process_one()) std::this_thread::sleep_for(std::chrono::nanoseconds(config_.poll_ns));
  }
}

}  // namespace hd::station
