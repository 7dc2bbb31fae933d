#pragma once
// The stream thread's bookkeeping of GigE frames by block id: what was lost, late, malformed or
// of the wrong format, and the sequence the consumer sees, continuous across restarts.

#include <cstdint>
#include <optional>

#include "drivers/gige/frame_id_unwrapper.h"
#include "drivers/gige/gige_stats.h"

namespace hd::drivers {

/// Every buffer Aravis hands back goes through exactly one of lost(), wrong_format(),
/// malformed() or admit(); an admitted frame that is converted then gets its consumer sequence
/// from sequence_for() and is counted by published().
///
/// Ids of frames that were not published still feed the unwrapper (lost and wrong-format ones),
/// so the next good frame shows no gap for them: each loss is counted once, in its own counter;
/// ids skipped before any of them are gaps.
///
/// The camera restarts its block ids when it is reopened, and stop()/start() restarts our
/// unwrapper; the consumer's sequence must never move backwards, so the first frame after either
/// follows the last one published, whatever its id.
///
/// Stream thread only, except the counters (GigeCounters: read from any thread).
class FrameAccounting {
 public:
  explicit FrameAccounting(GigeCounters& counters) : counters_(counters) {}

  /// start(): ids begin anew; a consumer sequence already handed out is continued.
  void start();
  /// A reconnect: the camera's ids restarted; the consumer sequence is continued.
  void reconnected();

  /// A frame the camera sent and Aravis could not complete (`status` an ArvBufferStatus other
  /// than SUCCESS): a bad buffer, its id consumed.
  void lost(uint64_t frame_id, int status);
  /// A frame of another size or pixel format than negotiated: never published, its id consumed.
  void wrong_format(uint64_t frame_id);
  /// Not an image, no data, or it would not convert: skipped, its id untouched (or already
  /// consumed by admit()).
  void malformed();

  /// An image frame of the negotiated format: its unwrapped camera sequence when it is the next
  /// one (the ids skipped before it are counted as gaps), nothing when it is late, a duplicate
  /// (counted late_or_duplicate) or an invalid id (counted malformed).
  std::optional<uint64_t> admit(uint64_t frame_id);

  /// The consumer's sequence for an admitted, converted frame with camera sequence
  /// `camera_sequence`, which is about to be published.
  uint64_t sequence_for(uint64_t camera_sequence);
  /// It was published.
  void published() { GigeCounters::bump(counters_.frames_published); }

  /// The consumer sequence of the newest frame published (0 before the first).
  uint64_t last_sequence() const { return last_sequence_; }

 private:
  // The ids `id` skipped (the frames before it that never arrived) into id_gaps.
  void count_gap(const FrameIdUnwrapper::Result& id);

  GigeCounters& counters_;
  FrameIdUnwrapper unwrapper_;
  bool got_first_frame_ = false;  // since the last start() or reconnected()
  bool rebase_sequence_ = false;  // the next sequence_for() continues from last_sequence_
  uint64_t sequence_offset_ = 0;  // consumer sequence - camera sequence (mod 2^64)
  uint64_t last_sequence_ = 0;
};

}  // namespace hd::drivers
