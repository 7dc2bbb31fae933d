#include "station/video/camera_pipeline.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "drivers/clock/monotonic_clock.h"
#include "station/video/calibration_difference.h"
#include "station/video/frame_copy.h"

namespace hd::station {
namespace {

// Slots of the calibrated size; without a calibration yet, empty (sized by the first frame).
drivers::Frame rgba_prototype(const core::Pinhole& p_c) {
  drivers::Frame f;
  if (p_c.valid()) f.allocate_rgba(p_c.width, p_c.height);
  return f;
}

bool same_intrinsics(const core::Pinhole& a, const core::Pinhole& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.distortion_count == b.distortion_count &&
         a.distortion == b.distortion;
}

// A write slot of the active size (resized only when a new calibration changed the size).
drivers::Frame& sized(drivers::Frame& slot, const core::Pinhole& p) {
  if (slot.width != p.width || slot.height != p.height || slot.data.empty())
    slot.allocate_rgba(p.width, p.height);
  return slot;
}

}  // namespace

CameraPipeline::CameraPipeline(drivers::CameraSource& source, CameraPipelineConfig config)
    : source_(source),
      config_(config),
      undistort_(config.p_c.valid() && Undistorter::needed(config.p_c)),
      undistorter_(undistort_ ? Undistorter(config.p_c) : Undistorter()),
      active_p_c_(config.p_c),
      model_period_ns_(std::isfinite(config.model_period_s) && config.model_period_s > 0
                           ? static_cast<int64_t>(std::llround(config.model_period_s * 1e9))
                           : 0),
      frames_(rgba_prototype(config.p_c)),
      model_frames_(rgba_prototype(config.p_c)) {
  if (config_.poll_ns <= 0) config_.poll_ns = 500'000;
  if (!config_.p_c.valid() && !config_.calibration_from_stream)
    throw std::invalid_argument("camera pipeline: camera intrinsics are not a valid pinhole");
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

bool CameraPipeline::adopt(const drivers::FrameCalibration& c) {
  const int64_t current = stream_revision_.load(std::memory_order_relaxed);
  if (current >= 0 && static_cast<uint32_t>(current) == c.revision) return true;
  const bool changed = !same_intrinsics(c.p_c, active_p_c_);
  if (changed) {
    try {
      const bool needed = Undistorter::needed(c.p_c);
      undistorter_ = needed ? Undistorter(c.p_c) : Undistorter();
      undistort_.store(needed, std::memory_order_relaxed);
    } catch (const std::invalid_argument&) {
      return false;  // the parser lets no such calibration through; refused all the same
    }
    active_p_c_ = c.p_c;
  }
  CalibrationEvent ev;
  ev.time_ns = drivers::monotonic_now_ns();
  ev.revision = c.revision;
  ev.p_c = c.p_c;
  ev.T_world_cam = c.T_world_cam;
  ev.first = current < 0;
  ev.intrinsics_changed = changed;
  ev.differs_from_file_px = config_.p_c.valid()
                                ? calibration_difference_px(config_.p_c, config_.T_world_cam, c.p_c,
                                                            c.T_world_cam, config_.compare_depth_m)
                                : NAN;
  calibration_events_.push(ev);
  stream_revision_.store(c.revision, std::memory_order_release);
  return true;
}

bool CameraPipeline::process_one() {
  drivers::Mailbox<drivers::Frame>& in = source_.frames();
  if (!in.fetch()) return false;
  const drivers::Frame& src = in.latest();
  if (src.calibration.present ? !adopt(src.calibration) : !active_p_c_.valid()) {
    uncalibrated_.fetch_add(1, std::memory_order_relaxed);
    return true;
  }
  const drivers::CameraFormat expected{active_p_c_.width, active_p_c_.height,
                                       drivers::PixelFormat::kRgba8, 0.0};
  if (!is_rgba_frame(src, expected.width_px, expected.height_px)) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    // State first: a consumer that sees the event must also see the camera as unusable.
    mismatch_.store(true, std::memory_order_release);
    format_watch_.lost(drivers::monotonic_now_ns(), drivers::FormatEventCause::kFrame, expected,
                       drivers::CameraFormat{src.width, src.height, src.format, 0.0});
    return true;
  }
  drivers::Frame& out = sized(frames_.write_slot(), active_p_c_);
  const bool ok = undistort_.load(std::memory_order_relaxed) ? undistorter_.apply(src, out)
                                                             : copy_frame(src, out);
  if (!ok) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    return true;
  }
  if (format_watch_.restored(drivers::monotonic_now_ns(), drivers::FormatEventCause::kFrame,
                             expected))
    mismatch_.store(false, std::memory_order_release);
  // The model's copy is taken from the finished frame (no second undistortion) before the
  // station can see it: after publish() the slot belongs to the mailbox.
  const int64_t t_ns = out.host_timestamp_ns;
  if (!model_sent_ || model_period_ns_ == 0 || t_ns - last_model_ns_ >= model_period_ns_ ||
      t_ns < last_model_ns_) {
    copy_frame(out, sized(model_frames_.write_slot(), active_p_c_));
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
