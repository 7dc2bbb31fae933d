#pragma once
// When a GigE camera's stream thread must look after the camera rather than its frames: a stall
// to probe, a lost camera to look for, a wrong format to put right. Decisions only; the camera
// does the probing and reopening.

#include <cstdint>

#include "drivers/source_state.h"

namespace hd::drivers {

/// Called once per turn of the stream thread (at least every pop timeout, 20 ms), after the
/// turn's buffer, with the camera's state. Every probe or reopen it asks for is rate-limited
/// here: a lost camera is looked for every `reopen_period_ns`, a stalled one probed at most once
/// per `stall_timeout_ns` (a live camera that merely paused stays stalled, it is not flooded).
///
/// The stream thread's own; not thread-safe.
class StreamWatchdog {
 public:
  struct Config {
    int64_t stall_timeout_ns = 250'000'000;  ///< no frame for this long: stalled, then probed
    int64_t reopen_period_ns = 500'000'000;  ///< how often a lost camera is looked for
  };

  enum class Step : uint8_t {
    kNone,  ///< nothing to do this turn
    /// Disconnected, or released after a mismatch: probe it; reopen it when it answers, and a
    /// released one that does not answer is disconnected.
    kProbeToReopen,
    kControlLost,  ///< Aravis's heartbeat lost control of it: disconnected
    /// It streams another format: release it and reopen it with our configuration.
    kRestoreFormat,
    kStalled,  ///< no frame for the stall timeout (and probed less than one timeout ago)
    /// Stalled, and time to probe it: a refused or unanswered probe means disconnected.
    kStalledProbe,
  };

  explicit StreamWatchdog(Config config) : config_(config) {}

  /// start(): frames are expected from `now_ns` on, and no probe was sent yet.
  void restart(int64_t now_ns) {
    last_frame_ns_ = now_ns;
    last_probe_ns_ = 0;
  }
  /// A frame was published (or the camera was reopened) at `now_ns`.
  void frame_at(int64_t now_ns) { last_frame_ns_ = now_ns; }
  /// The camera was first seen delivering another format at `now_ns`.
  void mismatch_at(int64_t now_ns) { mismatch_since_ns_ = now_ns; }

  /// What to do at `now_ns` for a camera in `state`; `released` when it holds no stream (released
  /// after a reconnect with other settings), `control_lost` when Aravis said so. A step that
  /// probes or reopens counts as the probe of this period.
  Step next(int64_t now_ns, SourceState state, bool released, bool control_lost);

 private:
  Config config_;
  int64_t last_frame_ns_ = 0;
  int64_t last_probe_ns_ = 0;
  int64_t mismatch_since_ns_ = 0;
};

}  // namespace hd::drivers
