#pragma once
// Whether a camera still delivers the format it negotiated: the lost / restored edges and the
// events they leave for the station, written once for every driver (GigE, V4L2, RTP) and the
// station's camera pipeline.
//
// One producer thread (the device's capture or streaming thread) calls lost() and restored();
// one consumer (the station) pops the events. A stream of wrong frames leaves one kLost event,
// not one per frame, and a kRestored event follows only a kLost one, so the station's report
// pairs them. The caller sets its state to kFormatMismatch before calling lost(): a consumer
// that sees the event must also see the camera as unusable.

#include <cstdint>

#include "drivers/format_event.h"

namespace hd::drivers {

class FormatWatch {
 public:
  /// The device delivers `seen`, not `expected`. Leaves a kLost event on the edge only; true
  /// then.
  bool lost(int64_t time_ns, FormatEventCause cause, const CameraFormat& expected,
            const CameraFormat& seen) {
    if (lost_) return false;
    lost_ = true;
    events_.push(FormatEvent{time_ns, FormatEventKind::kLost, cause, expected, seen});
    return true;
  }

  /// It delivers `expected` again. Leaves a kRestored event only after a kLost one; true then.
  bool restored(int64_t time_ns, FormatEventCause cause, const CameraFormat& expected) {
    if (!lost_) return false;
    lost_ = false;
    events_.push(FormatEvent{time_ns, FormatEventKind::kRestored, cause, expected, expected});
    return true;
  }

  /// A new negotiation: what was lost before no longer applies, and no event says so.
  void forget() { lost_ = false; }

  /// A kLost event was left and no kRestored since (the producer's thread).
  bool is_lost() const { return lost_; }

  /// The station's side: the oldest event not yet read.
  bool pop(FormatEvent& out) { return events_.pop(out); }

  /// Events dropped because the station did not read them (a full ring).
  uint64_t overflowed() const { return events_.overflowed(); }

 private:
  bool lost_ = false;
  FormatEventRing events_;
};

}  // namespace hd::drivers
