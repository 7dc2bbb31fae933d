#include "drivers/gige/frame_id_unwrapper.h"

namespace hd::drivers {

FrameIdUnwrapper::Result FrameIdUnwrapper::update(uint64_t block_id) {
  Result r;
  if (block_id > kCycle16) extended_ = true;
  if (!extended_ && block_id == 0) return r;  // reserved in 16-bit GVSP: not a frame id
  if (!started_) {
    started_ = true;
    last_id_ = block_id;
    sequence_ = block_id;  // start on the device's own count, so unwrapped == raw until a wrap
    r.verdict = Verdict::kNext;
    r.sequence = sequence_;
    return r;
  }
  uint64_t delta = 0;
  if (extended_ && last_id_ <= kCycle16 && block_id > kCycle16) {
    delta = block_id > last_id_ ? block_id - last_id_ : 0;  // switched to extended ids mid-stream
  } else if (extended_) {
    if (block_id <= last_id_) {
      ++late_;
      r.verdict = Verdict::kDuplicateOrLate;
      return r;
    }
    delta = block_id - last_id_;
  } else {
    // Ids 1..65535 as 0..65534 on a cycle; forward distance modulo the cycle.
    delta = ((block_id - 1) + kCycle16 - (last_id_ - 1)) % kCycle16;
    if (delta == 0 || delta > kCycle16 / 2) {
      ++late_;
      r.verdict = Verdict::kDuplicateOrLate;
      return r;
    }
  }
  if (delta == 0) {
    ++late_;
    r.verdict = Verdict::kDuplicateOrLate;
    return r;
  }
  last_id_ = block_id;
  sequence_ += delta;
  r.verdict = Verdict::kNext;
  r.sequence = sequence_;
  r.gap = delta - 1;
  dropped_ += r.gap;
  return r;
}

}  // namespace hd::drivers
