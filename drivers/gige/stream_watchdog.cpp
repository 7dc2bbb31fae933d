// StreamWatchdog: the stream thread's stall, loss and mismatch decisions for a GigE camera.
#include "drivers/gige/stream_watchdog.h"

namespace hd::drivers {

StreamWatchdog::Step StreamWatchdog::next(int64_t now_ns, SourceState state, bool released,
                                          bool control_lost) {
  if (state == SourceState::kDisconnected || (state == SourceState::kFormatMismatch && released)) {
    // Reopen when the camera answers again (it was power-cycled, replugged or restarted), or try
    // again whether one that answered with other settings now takes ours.
    if (now_ns - last_probe_ns_ < config_.reopen_period_ns) return Step::kNone;
    last_probe_ns_ = now_ns;
    return Step::kProbeToReopen;
  }
  if (control_lost) return Step::kControlLost;
  if (state == SourceState::kFormatMismatch) {
    // Streaming frames of another format (someone else reconfigured it, or it changed by itself):
    // put our configuration back now and then, until the format is right again.
    if (now_ns - mismatch_since_ns_ < config_.reopen_period_ns ||
        now_ns - last_probe_ns_ < config_.reopen_period_ns)
      return Step::kNone;
    last_probe_ns_ = now_ns;
    return Step::kRestoreFormat;
  }
  if (now_ns - last_frame_ns_ <= config_.stall_timeout_ns) return Step::kNone;
  // Probe at most once per stall timeout: a live camera that merely paused stays "stalled".
  if (now_ns - last_probe_ns_ < config_.stall_timeout_ns) return Step::kStalled;
  last_probe_ns_ = now_ns;
  return Step::kStalledProbe;
}

}  // namespace hd::drivers
