#pragma once
// A CameraSource that plays recorded images as a camera: one frame per image, in order, at a set
// rate, each stamped with its exposure time on the station's clock, none lost.
//
// It behaves like a recording played back (or a camera with a deep frame queue), not like a
// sensor that overwrites: frame k is published no earlier than its exposure time and only once
// the consumer has taken frame k - 1, so a slow consumer sees every frame, late, with the time it
// was taken. Several replay cameras given the same epoch are a rig on one trigger: frame k of
// each is exposed at epoch + offset + k / rate. After the last image the stream ends and state()
// is kClosed.

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "drivers/camera_source.h"

namespace hd::drivers {

/// One recorded picture, 8-bit gray.
struct ReplayImage {
  std::string name;  ///< for messages (the file name)
  int width = 0;
  int height = 0;
  std::vector<uint8_t> gray;  ///< width * height bytes, rows packed
};

struct ReplayCameraConfig {
  std::string id = "replay";
  double rate_hz = 15.0;
  /// Exposure times shifted by this much against the epoch (a camera out of step with its rig).
  int64_t offset_ns = 0;
  /// Called by open(); returns the pictures in play order (all the same size). May throw: open()
  /// reports it as a DeviceError naming the id.
  std::function<std::vector<ReplayImage>()> load{};
  /// Host time of frame 0's exposure (before offset_ns), shared by the cameras of one rig. Called
  /// once, by start(). Empty: the time of start().
  std::function<int64_t()> epoch_ns{};
};

class ReplayCamera : public CameraSource {
 public:
  explicit ReplayCamera(ReplayCameraConfig config);
  ~ReplayCamera() override;
  ReplayCamera(const ReplayCamera&) = delete;
  ReplayCamera& operator=(const ReplayCamera&) = delete;

  std::string id() const override { return config_.id; }
  /// Loads the pictures; throws DeviceError naming the id when there are none, they differ in
  /// size, or the rate is outside (0, 1000] Hz.
  void open() override;
  void start() override;
  void stop() override;
  /// kStreaming while playing, kClosed before start(), after stop() and once the last picture was
  /// published (the recording ended).
  SourceState state() const override;
  uint64_t dropped_frames() const override { return 0; }  ///< a recording loses nothing
  Mailbox<Frame>& frames() override { return frames_; }
  /// The pictures' size as RGBA8 at the configured rate (unknown before open()).
  CameraFormat format() const override;
  /// Pictures loaded by open().
  std::size_t image_count() const { return images_.size(); }

 private:
  void run(int64_t epoch_ns);
  ReplayCameraConfig config_;
  std::vector<ReplayImage> images_;
  std::atomic<bool> running_{false};
  std::atomic<bool> ended_{false};
  std::thread thread_;
  Mailbox<Frame> frames_;
};

}  // namespace hd::drivers
