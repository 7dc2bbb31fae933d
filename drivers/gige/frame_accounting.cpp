// FrameAccounting: GigE frame ids to counters and the consumer's continuous sequence.
#include "drivers/gige/frame_accounting.h"

namespace hd::drivers {

void FrameAccounting::start() {
  unwrapper_.reset();
  got_first_frame_ = false;
  rebase_sequence_ = last_sequence_ != 0;  // a restart must not move the sequence backwards
}

void FrameAccounting::reconnected() {
  unwrapper_.reset();
  got_first_frame_ = false;
  rebase_sequence_ = true;  // the camera's ids restarted; the consumer's sequence must not
}

void FrameAccounting::lost(uint64_t frame_id, int status) {
  // The frame is lost, but its id is known: feed it, so the next frame shows no gap and the loss
  // is counted once; the ids skipped before it are gaps, as before an admitted frame.
  count_gap(unwrapper_.update(frame_id));
  GigeCounters::bump(counters_.bad_buffers);
  if (!got_first_frame_) GigeCounters::bump(counters_.bad_before_first_frame);
  counters_.last_bad_status.store(status, std::memory_order_relaxed);
}

void FrameAccounting::wrong_format(uint64_t frame_id) {
  count_gap(unwrapper_.update(frame_id));
  GigeCounters::bump(counters_.wrong_format);
}

void FrameAccounting::malformed() {
  GigeCounters::bump(counters_.malformed);
}

std::optional<uint64_t> FrameAccounting::admit(uint64_t frame_id) {
  const auto id = unwrapper_.update(frame_id);
  if (id.verdict != FrameIdUnwrapper::Verdict::kNext) {
    GigeCounters::bump(id.verdict == FrameIdUnwrapper::Verdict::kInvalid
                           ? counters_.malformed
                           : counters_.late_or_duplicate);
    return std::nullopt;
  }
  count_gap(id);
  return id.sequence;
}

void FrameAccounting::count_gap(const FrameIdUnwrapper::Result& id) {
  if (id.verdict != FrameIdUnwrapper::Verdict::kNext || id.gap == 0) return;
  GigeCounters::bump(counters_.id_gaps, id.gap);
  // admit() counts the first good frame's gap before sequence_for() marks it: still before it.
  if (!got_first_frame_) GigeCounters::bump(counters_.gaps_before_first_frame, id.gap);
}

uint64_t FrameAccounting::sequence_for(uint64_t camera_sequence) {
  got_first_frame_ = true;
  if (rebase_sequence_) {
    // Unsigned wrap-around arithmetic: the first frame after a restart follows the last one.
    sequence_offset_ = last_sequence_ + 1 - camera_sequence;
    rebase_sequence_ = false;
  }
  last_sequence_ = camera_sequence + sequence_offset_;
  return last_sequence_;
}

}  // namespace hd::drivers
