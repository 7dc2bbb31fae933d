#pragma once
// The station's per-camera video path: undistortion and the tee to the model updater.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "core/pinhole.h"
#include "drivers/camera_source.h"
#include "station/video/undistorter.h"

namespace hd::station {

struct CameraPipelineConfig {
  /// The camera's calibrated intrinsics. Frames from the wrapped source must be RGBA8 of
  /// p_c.width x p_c.height; they are undistorted with p_c.distortion when any coefficient is
  /// non-zero (else copied), so every published frame matches the pinhole of p_c.
  core::Pinhole p_c;
  /// At most one frame per this period also goes to `model_frames()` (the model updater's
  /// mailbox). <= 0: every frame.
  double model_period_s = 0.5;
  /// How long the pipeline thread sleeps when no new frame has arrived (the driver's mailbox
  /// has no wake-up; 0.5 ms adds at most that much to the video age).
  int64_t poll_ns = 500'000;
};

/// A CameraSource decorator the station reads instead of the device: its own thread takes each
/// new frame of the wrapped source (a driver or a mock camera; this pipeline is that mailbox's
/// single consumer), undistorts or copies it into `frames()` with sequence and all timestamps
/// untouched, and, at most every `model_period_s` (by host timestamp), also into
/// `model_frames()`. id(), format() and negotiate() are the wrapped source's; dropped_frames() adds
/// the frames this pipeline rejected (`rejected()`). A frame of another size or format than p_c's
/// (a source that cannot say its format before its first frame, or one whose driver missed a
/// change) is never published: state() is kFormatMismatch from that frame until one of the right
/// size arrives, and both moments are FormatEvents (pop_format_event() returns the source's and
/// the pipeline's). All buffers are sized in the constructor: nothing is allocated per frame.
/// stop() joins within about one poll period plus the time of one frame's undistortion.
class CameraPipeline final : public drivers::CameraSource {
 public:
  /// `source` must outlive the pipeline. Throws std::invalid_argument when p_c is not valid.
  CameraPipeline(drivers::CameraSource& source, CameraPipelineConfig config);
  ~CameraPipeline() override;  ///< stops
  CameraPipeline(const CameraPipeline&) = delete;
  CameraPipeline& operator=(const CameraPipeline&) = delete;

  std::string id() const override { return source_.id(); }
  void open() override;   ///< opens the wrapped source (DeviceError passes through)
  void start() override;  ///< starts the wrapped source, then the pipeline thread
  void stop() override;   ///< joins the pipeline thread, then stops the wrapped source
  drivers::SourceState state() const override {
    return mismatch_.load(std::memory_order_acquire) ? drivers::SourceState::kFormatMismatch
                                                     : source_.state();
  }
  drivers::FormatNegotiation negotiate(const drivers::CameraFormatRequest& wanted) override {
    return source_.negotiate(wanted);
  }
  drivers::CameraFormat format() const override { return source_.format(); }
  bool pop_format_event(drivers::FormatEvent& out) override {
    return source_.pop_format_event(out) || events_.pop(out);
  }
  uint64_t dropped_frames() const override;
  drivers::Mailbox<drivers::Frame>& frames() override { return frames_; }

  /// The model updater's mailbox (single consumer, like frames()).
  drivers::Mailbox<drivers::Frame>& model_frames() { return model_frames_; }

  bool undistorting() const { return undistort_; }
  const core::Pinhole& p_c() const { return config_.p_c; }
  uint64_t processed() const { return processed_.load(std::memory_order_relaxed); }
  /// Frames of the wrong size or format (not published).
  uint64_t rejected() const { return rejected_.load(std::memory_order_relaxed); }
  /// Frames the wrapped device lost (its dropped_frames(): sequence gaps, bad buffers, overruns).
  uint64_t device_dropped_frames() const { return source_.dropped_frames(); }
  /// Frames also published to model_frames().
  uint64_t model_published() const { return model_frames_.published(); }

  /// Processes one frame from the wrapped source if a new one is there (what the thread does in
  /// a loop). Returns whether one was taken. Only for tests that drive the pipeline without
  /// start(); never call it while the thread runs.
  bool process_one();

 private:
  void run();

  drivers::CameraSource& source_;
  CameraPipelineConfig config_;
  bool undistort_ = false;
  Undistorter undistorter_;
  int64_t model_period_ns_ = 0;
  int64_t last_model_ns_ = 0;
  bool model_sent_ = false;
  drivers::Mailbox<drivers::Frame> frames_;
  drivers::Mailbox<drivers::Frame> model_frames_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> processed_{0};
  std::atomic<uint64_t> rejected_{0};
  std::atomic<bool> mismatch_{false};
  drivers::FormatEventRing events_;
  std::thread thread_;
};

}  // namespace hd::station
