#pragma once
// Which well-formed RTP media packets belong to the live stream: one SSRC at a time, and only
// sequence numbers and RTP times a live sender of that SSRC can send. The network camera asks it
// for every packet of its payload type before rtpbin sees the packet.
//
// Why: GStreamer 1.22's rtpjitterbuffer trusts the numbers. For video (many packets share an RTP
// time, so it does not assume equidistant packets) a packet whose sequence number jumps N ahead
// makes it add one retransmission timer per missing packet, all due at once; its timer thread
// then sends N retransmission requests through rtprtxreceive and rtpsession while the
// jitter-buffer lock blocks udpsrc's thread, and every further wild number adds thousands more
// (the camera stopped receiving after a few hundred mutated datagrams). A wild RTP time moves
// its timestamp extension and skew estimate instead. So such packets never reach it.
//
// The rule is RFC 3550 appendix A.1's: a packet up to kMaxSequenceJump ahead of the highest
// sequence number (a loss) or up to kMaxMisorder behind it (reordered, duplicated) is the
// stream's; one further away is refused unless the next packet follows it (seq + 1, RTP time
// close): two consecutive packets are a sender that renumbered, and the stream resynchronises
// to them (counted). The highest number moves with each next packet, and past a gap only when a
// second packet agrees, so that stray numbers taken within the window cannot carry it away from
// the stream's. An accepted sequence number must also bring a plausible RTP time: at most
// kMaxRtpTimeBehind behind the highest packet's, and at most kMaxRtpTimeAhead plus the arrival
// time passed since the last accepted packet ahead of it (90 kHz clock). After silence_ns
// without an accepted packet (a cut link, a restarted sender) any packet starts the stream
// afresh, of its own SSRC.
//
// Pure: the caller passes the arrival time. Not thread-safe (udpsrc's streaming thread owns it).

#include <cstdint>

#include "drivers/rtp/rtp_packet.h"

namespace hd::drivers {

class RtpStreamGuard {
 public:
  static constexpr int kMaxSequenceJump = 128;  ///< packets ahead: a loss burst at most this long
  /// Packets behind: as far as a jump ahead may go (RFC 3550 A.1 has 100), so that the stream
  /// still passes behind a stray packet taken within kMaxSequenceJump (the jitter buffer then
  /// drops what it has already passed as late).
  static constexpr int kMaxMisorder = kMaxSequenceJump;
  static constexpr int64_t kClockRateHz = 90'000;       ///< H.264's RTP clock (RFC 6184)
  static constexpr int64_t kMaxRtpTimeAhead = 90'000;   ///< 1 s beyond the arrival time passed
  static constexpr int64_t kMaxRtpTimeBehind = 90'000;  ///< 1 s

  explicit RtpStreamGuard(int64_t silence_ns) : silence_ns_(silence_ns) {}

  /// kNone: the stream's (its state moves on); kOtherSsrc, kSequenceJump or kRtpTimeJump:
  /// refused (the state stays, except that a refused sequence jump is remembered as the start
  /// of a possible renumbering).
  RtpPacketError check(const RtpPacketView& packet, int64_t arrival_ns);

  uint64_t resyncs() const { return resyncs_; }  ///< renumberings taken (two consecutive packets)
  uint64_t starts() const { return starts_; }    ///< streams started (first, after a silence)

 private:
  void take(const RtpPacketView& packet, int64_t arrival_ns);

  int64_t silence_ns_;
  bool live_ = false;
  uint32_t ssrc_ = 0;
  uint16_t max_seq_ = 0;  // the highest sequence number accepted
  uint32_t max_ts_ = 0;   // the RTP time of that packet
  int64_t last_ns_ = 0;   // arrival of the last accepted packet
  // A packet taken ahead of the highest after a gap, waiting for a second one to agree.
  bool gap_pending_ = false;
  uint16_t gap_seq_ = 0;
  // A refused jump: the sequence number and RTP time the next packet must have to confirm it.
  bool candidate_ = false;
  uint16_t candidate_seq_ = 0;
  uint32_t candidate_ts_ = 0;
  uint64_t resyncs_ = 0, starts_ = 0;
};

}  // namespace hd::drivers
