#pragma once
// A scene's camera driven by the scene's clock instead of a thread: advance_to(t) delivers what
// the running device (a MockCamera of the Simulation) would have delivered by host time t, the
// same frames with the same exposure times, delays and drops (Simulation::frame_timing), so a
// run stepped frame by frame (`hybrid-station score`) sees the inputs the scene's effects say,
// whatever the machine's speed.
//
// Host time = epoch_ns + scene time. Frames are delivered in sequence order, each at
// max(its exposure + delay, the previous one's delivery), as the device's thread does; a
// dropped frame is counted and never delivered. Only the newest frame due by t is rendered (the
// mailbox would hand the station nothing older).

#include <cstdint>
#include <string>

#include "drivers/camera_source.h"
#include "sim/simulation.h"

namespace hd::sim {

class SteppedCamera final : public drivers::CameraSource {
 public:
  /// Camera `index` of `sim` (which must outlive it), with scene t = 0 at host time epoch_ns.
  SteppedCamera(Simulation& sim, std::size_t index, int64_t epoch_ns);

  std::string id() const override { return id_; }
  void open() override {}
  drivers::FormatNegotiation negotiate(const drivers::CameraFormatRequest& wanted) override;
  drivers::CameraFormat format() const override { return format_; }
  void start() override { running_ = true; }
  void stop() override { running_ = false; }
  /// Streaming from start() to stop(): a scene's stalls are its frame timing's (delays, drops).
  drivers::SourceState state() const override;
  uint64_t dropped_frames() const override { return dropped_; }
  drivers::Mailbox<drivers::Frame>& frames() override { return mailbox_; }

  /// Delivers every frame due by host time now_ns (renders and publishes the newest). Returns
  /// whether a new frame was published.
  bool advance_to(int64_t now_ns);
  uint64_t delivered() const { return delivered_; }

 private:
  Simulation& sim_;
  std::size_t index_;
  int64_t epoch_ns_;
  std::string id_;
  drivers::CameraFormat format_;
  drivers::Mailbox<drivers::Frame> mailbox_;
  bool running_ = false;
  uint64_t next_sequence_ = 0;
  int64_t last_delivery_ns_ = 0;
  uint64_t dropped_ = 0;
  uint64_t delivered_ = 0;
};

}  // namespace hd::sim
