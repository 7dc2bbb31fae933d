#include "drivers/rtp/frame_end_watch.h"

namespace hd::drivers {

void FrameEndWatch::on_packet(uint16_t sequence, bool marker, int64_t arrival_ns) {
  // Behind the newest (a repair of an earlier gap, a reordered packet): the jitter buffer's.
  if (started_ && static_cast<int16_t>(sequence - highest_) <= 0) return;
  started_ = true;
  highest_ = sequence;
  tries_ = 0;
  due_ns_ = marker ? 0 : arrival_ns + s_.wait_ns;
}

std::optional<uint16_t> FrameEndWatch::on_due(int64_t now_ns) {
  if (due_ns_ == 0 || now_ns < due_ns_) return std::nullopt;
  ++tries_;
  ++requests_;
  due_ns_ = tries_ < s_.max_requests ? now_ns + s_.retry_ns : 0;
  return static_cast<uint16_t>(highest_ + 1);
}

}  // namespace hd::drivers
