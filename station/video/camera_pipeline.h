#pragma once
// The station's per-camera video path: undistortion and the tee to the model updater.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "core/pinhole.h"
#include "core/pose.h"
#include "drivers/camera_source.h"
#include "drivers/format_watch.h"
#include "drivers/spsc_ring.h"
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
  /// The file's P_c (for comparing a streamed calibration with the file's) and the depth the
  /// two are compared at (the camera's plane distance d).
  core::Pose T_world_cam = core::Pose::identity();
  double compare_depth_m = 1.0;
  /// No calibration file (p_c not valid): the frames bring their calibration (a network camera
  /// whose sender streams it). Without this an invalid p_c is refused.
  bool calibration_from_stream = false;
};

/// A calibration the pipeline took from the stream (Frame::calibration) for the first time or at
/// a new revision; the frames from then on are undistorted with it.
struct CalibrationEvent {
  int64_t time_ns = 0;  ///< CLOCK_MONOTONIC
  uint32_t revision = 0;
  core::Pinhole p_c;
  core::Pose T_world_cam;
  bool first = false;               ///< the first calibration from the stream
  bool intrinsics_changed = false;  ///< the undistortion was rebuilt for it
  /// calibration_difference_px from the file's calibration at compare_depth_m; NaN: no file.
  double differs_from_file_px = 0.0;
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
///
/// Calibration from the stream: a frame that carries one (Frame::calibration, a network camera
/// whose sender streams p_c and P_c) is undistorted with it and published with it, whether or
/// not p_c came from a file (the stream wins); each new revision is a CalibrationEvent, and new
/// intrinsics rebuild the undistortion and, for a new size, the output slots (on this thread,
/// never the consumer's). Without a file (p_c not valid) a frame without one is never published
/// (counted in uncalibrated()), so the camera cannot be shown with a guessed calibration.
/// stop() joins within about one poll period plus the time of one frame's undistortion.
class CameraPipeline final : public drivers::CameraSource {
 public:
  /// `source` must outlive the pipeline. Throws std::invalid_argument when p_c is not valid,
  /// unless calibration_from_stream (then the frames must bring their calibration).
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
    return source_.pop_format_event(out) || format_watch_.pop(out);
  }
  uint64_t dropped_frames() const override;
  drivers::Mailbox<drivers::Frame>& frames() override { return frames_; }

  /// The model updater's mailbox (single consumer, like frames()).
  drivers::Mailbox<drivers::Frame>& model_frames() { return model_frames_; }

  bool undistorting() const { return undistort_.load(std::memory_order_relaxed); }
  const core::Pinhole& p_c() const { return config_.p_c; }  ///< the file's (invalid: none)
  /// Frames not published because neither a file nor the frame gave a calibration.
  uint64_t uncalibrated() const { return uncalibrated_.load(std::memory_order_relaxed); }
  /// The revision of the stream's calibration in use; -1 none (the file's, or nothing yet).
  int64_t stream_revision() const { return stream_revision_.load(std::memory_order_acquire); }
  /// The oldest calibration event not taken yet (single consumer; the ring holds 64).
  bool pop_calibration_event(CalibrationEvent& out) { return calibration_events_.pop(out); }
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
  bool adopt(const drivers::FrameCalibration& c);

  drivers::CameraSource& source_;
  CameraPipelineConfig config_;
  std::atomic<bool> undistort_{false};
  Undistorter undistorter_;
  core::Pinhole active_p_c_;  // the calibration frames are checked and undistorted with
  std::atomic<int64_t> stream_revision_{-1};
  std::atomic<uint64_t> uncalibrated_{0};
  drivers::SpscRing<CalibrationEvent, 64> calibration_events_;
  int64_t model_period_ns_ = 0;
  int64_t last_model_ns_ = 0;
  bool model_sent_ = false;
  drivers::Mailbox<drivers::Frame> frames_;
  drivers::Mailbox<drivers::Frame> model_frames_;
  std::atomic<bool> running_{false};
  std::atomic<uint64_t> processed_{0};
  std::atomic<uint64_t> rejected_{0};
  std::atomic<bool> mismatch_{false};
  drivers::FormatWatch format_watch_;  // this pipeline's own refusals (size, pixel format)
  std::thread thread_;
};

}  // namespace hd::station
