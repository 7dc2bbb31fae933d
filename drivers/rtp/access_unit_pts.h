#pragma once
// One PTS per access unit at the depayloader's input, never shared with another access unit.
// rtpjitterbuffer never lets its output PTS go backwards: a frame whose computed time would
// (jitter, a skew re-estimate) gets the previous frame's PTS. RtpFrameStamper keys a frame's stages
// by PTS, so two frames then shared one slot: the earlier took the later one's capture time (after
// its own arrival, "capture after arrival") and the later one was "not newer" and withheld; 10 and
// 8 frames in one faults-table cell (1 % loss, 0-20 ms jitter, RTX) under load, ASan, 2026-12-05.
// Pure: RTP time and PTS in, PTS out (the camera writes it on the packet).

#include <cstdint>

namespace hd::drivers {

class AccessUnitPts {
 public:
  /// A packet that starts another access unit at or before the previous one's PTS is moved this
  /// far after it: far below a frame period, so the decoder's timing does not change.
  static constexpr uint64_t kNudgeNs = 1'000;
  /// A PTS further back than this is the jitter buffer starting over (a new stream, a resync),
  /// not a clamp: taken as it is.
  static constexpr uint64_t kResyncNs = 1'000'000'000;

  /// The PTS a packet of RTP time `rtp_time` with the jitter buffer's `pts` should carry: its
  /// access unit's (the first packet's, moved past the previous access unit's when needed).
  uint64_t next(uint32_t rtp_time, uint64_t pts) {
    if (have_ && rtp_time == rtp_time_) return pts_;  // a later packet of the same access unit
    uint64_t out = pts;
    if (have_ && pts <= pts_ && pts_ - pts < kResyncNs) {
      out = pts_ + kNudgeNs;
      ++nudged_;
    }
    have_ = true;
    rtp_time_ = rtp_time;
    pts_ = out;
    return out;
  }
  /// Access units whose PTS was moved.
  uint64_t nudged() const { return nudged_; }

 private:
  bool have_ = false;
  uint32_t rtp_time_ = 0;
  uint64_t pts_ = 0;
  uint64_t nudged_ = 0;
};

}  // namespace hd::drivers
