#include "drivers/rtp/rtp_stream_guard.h"

namespace hd::drivers {

void RtpStreamGuard::take(const RtpPacketView& p, int64_t arrival_ns) {
  live_ = true;
  ssrc_ = p.ssrc;
  max_seq_ = p.sequence;
  max_ts_ = p.timestamp;
  last_ns_ = arrival_ns;
  candidate_ = false;
  gap_pending_ = false;
}

RtpPacketError RtpStreamGuard::check(const RtpPacketView& p, int64_t arrival_ns) {
  const int64_t elapsed_ns = arrival_ns - last_ns_;
  if (!live_ || elapsed_ns >= silence_ns_) {  // nothing live to compare with: a new stream
    ++starts_;
    take(p, arrival_ns);
    return RtpPacketError::kNone;
  }
  if (p.ssrc != ssrc_) return RtpPacketError::kOtherSsrc;
  // Differences in serial-number arithmetic (RFC 1982): the sign says ahead or behind.
  const int seq_delta = static_cast<int16_t>(static_cast<uint16_t>(p.sequence - max_seq_));
  const int64_t ts_delta = static_cast<int32_t>(p.timestamp - max_ts_);
  if (seq_delta > kMaxSequenceJump || seq_delta < -kMaxMisorder) {
    if (candidate_ && p.sequence == candidate_seq_ &&
        static_cast<int32_t>(p.timestamp - candidate_ts_) >= -kMaxRtpTimeBehind &&
        static_cast<int32_t>(p.timestamp - candidate_ts_) <= kMaxRtpTimeAhead) {
      ++resyncs_;  // two consecutive packets in the new numbering: the sender renumbered
      take(p, arrival_ns);
      return RtpPacketError::kNone;
    }
    candidate_ = true;
    candidate_seq_ = static_cast<uint16_t>(p.sequence + 1);
    candidate_ts_ = p.timestamp;
    return RtpPacketError::kSequenceJump;
  }
  // The RTP time may run ahead of the arrival time by a burst (frames sent late, all at once),
  // never by more than a second beyond the time that passed; it goes back only by reordering.
  const int64_t ahead_limit =
      kMaxRtpTimeAhead + (elapsed_ns > 0 ? elapsed_ns * kClockRateHz / 1'000'000'000 : 0);
  if (ts_delta < -kMaxRtpTimeBehind || ts_delta > ahead_limit) return RtpPacketError::kRtpTimeJump;
  // The highest number moves with the next packet, or after a gap once a second packet agrees
  // (is ahead of the first within the window): a stray number taken within the window alone
  // never moves it, so strays cannot ratchet it away from the stream.
  const bool agrees =
      gap_pending_ && static_cast<int16_t>(static_cast<uint16_t>(p.sequence - gap_seq_)) > 0 &&
      static_cast<int16_t>(static_cast<uint16_t>(p.sequence - gap_seq_)) <= kMaxSequenceJump;
  if (seq_delta == 1 || (seq_delta > 1 && agrees)) {
    max_seq_ = p.sequence;
    max_ts_ = p.timestamp;
    gap_pending_ = false;
  } else if (seq_delta > 1) {
    gap_pending_ = true;
    gap_seq_ = p.sequence;
  }
  last_ns_ = arrival_ns;
  return RtpPacketError::kNone;
}

}  // namespace hd::drivers
