#pragma once
// What a GigeCamera counts while it streams (GigeStats), the atomic counters behind it, and the
// per-frame hand-off timing it records for latency measurement.

#include <atomic>
#include <cstdint>

namespace hd::drivers {

/// When one frame crossed each stage, for latency measurement (CLOCK_MONOTONIC ns).
struct GigeHandoffTiming {
  uint64_t sequence = 0;
  int64_t arrival_ns = 0;    ///< the frame's leader packet landed (Aravis buffer system time)
  int64_t popped_ns = 0;     ///< our stream thread took it from Aravis's output queue
  int64_t published_ns = 0;  ///< converted and published into the mailbox
};

/// Counters since start(); read from any thread.
struct GigeStats {
  uint64_t frames_published = 0;
  uint64_t bad_buffers = 0;        ///< ARV_BUFFER_STATUS != SUCCESS (missing packets, timeout...)
  uint64_t id_gaps = 0;            ///< frames missing from the block-id sequence
  uint64_t late_or_duplicate = 0;  ///< ids at or before the newest one, skipped
  uint64_t malformed = 0;          ///< not an image payload, or unconvertible, skipped
  /// Frames of another size or pixel format than negotiated (ARV_BUFFER_STATUS_SIZE_MISMATCH
  /// included): never published; the first of a run of them is a FormatEvent.
  uint64_t wrong_format = 0;
  uint64_t liveness_probes = 0;
  int last_bad_status = 0;  ///< ArvBufferStatus of the newest bad buffer (0 = none yet)
  uint64_t reconnects = 0;  ///< times a lost camera answered again and streams anew
  /// Times a lost or mismatched camera that answered was opened again (successful or not).
  uint64_t reopen_attempts = 0;
  /// Of bad_buffers, those before the first good frame of a start or reconnect (a stream that
  /// began mid-frame, or a first frame Aravis timed out while the host was busy starting).
  uint64_t bad_before_first_frame = 0;
  /// Of id_gaps, those before the first good frame of a start or reconnect (ids skipped between
  /// a lost first frame and the first good one).
  uint64_t gaps_before_first_frame = 0;
};

/// GigeStats as it is counted: the stream thread adds, any thread takes a snapshot. Relaxed
/// atomics: each counter is exact on its own, a snapshot is not one instant across all of them.
struct GigeCounters {
  std::atomic<uint64_t> frames_published{0};
  std::atomic<uint64_t> bad_buffers{0};
  std::atomic<uint64_t> id_gaps{0};
  std::atomic<uint64_t> late_or_duplicate{0};
  std::atomic<uint64_t> malformed{0};
  std::atomic<uint64_t> wrong_format{0};
  std::atomic<uint64_t> liveness_probes{0};
  std::atomic<int> last_bad_status{0};
  std::atomic<uint64_t> reconnects{0};
  std::atomic<uint64_t> reopen_attempts{0};
  std::atomic<uint64_t> bad_before_first_frame{0};
  std::atomic<uint64_t> gaps_before_first_frame{0};

  /// Adds one to `counter` (relaxed: a count, not a signal to another thread).
  static void bump(std::atomic<uint64_t>& counter, uint64_t n = 1) {
    counter.fetch_add(n, std::memory_order_relaxed);
  }

  GigeStats snapshot() const;

  /// Frames the camera sent that the consumer never got: bad buffers and gaps in the ids.
  uint64_t dropped() const {
    return bad_buffers.load(std::memory_order_relaxed) + id_gaps.load(std::memory_order_relaxed);
  }
};

}  // namespace hd::drivers
