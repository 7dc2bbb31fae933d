#pragma once
// The one interface every head pose device (HID tracker, mock, replay) offers the station.

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/pose.h"
#include "drivers/mailbox.h"
#include "drivers/source_state.h"
#include "drivers/spsc_ring.h"

namespace hd::drivers {

/// One head pose measurement in the tracker's reference frame.
struct PoseSample {
  core::Pose T_tracker_head;  ///< head (camera axes) to tracker frame
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();  ///< in the head frame
  bool has_angular_velocity = false;
  bool has_position = false;   ///< false: orientation-only tracker
  uint32_t reset_counter = 0;  ///< bumps when the tracker's reference frame jumps
  uint64_t sequence = 0;
  int64_t device_timestamp_ns = 0;
  int64_t host_timestamp_ns = 0;  ///< CLOCK_MONOTONIC
  bool device_time_trusted = false;
};

/// A head pose device. Its thread publishes every sample to `history()` (for prediction) and the
/// newest to `latest()`.
class PoseSource {
 public:
  virtual ~PoseSource() = default;
  virtual std::string id() const = 0;
  virtual void open() = 0;
  virtual void start() = 0;
  virtual void stop() = 0;
  virtual SourceState state() const = 0;
  virtual uint64_t rejected_reports() const = 0;  ///< malformed input, counted and skipped
  virtual Mailbox<PoseSample>& latest() = 0;
  virtual SpscRing<PoseSample, 1024>& history() = 0;
};

}  // namespace hd::drivers
