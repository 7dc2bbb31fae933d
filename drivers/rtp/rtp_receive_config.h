#pragma once
// Settings of the station's network camera (one RTP H.264 stream), as data.

#include <cstdint>
#include <optional>
#include <string>

#include "drivers/rtp/rtp_uri.h"
#include "drivers/rtp/srtp_key.h"

namespace hd::drivers {

/// Everything the receive pipeline is built from (rtp_receive_pipeline.h turns it into a
/// GStreamer description). Times in ms where GStreamer takes ms.
struct RtpReceiveConfig {
  RtpAddress listen;  ///< RTP on listen.port, RTCP on listen.port + 1
  /// rtpbin latency, ms: small, video is only useful when fresh. With jitter_buffer_auto, the
  /// least the measured budget may set.
  int jitter_buffer_latency_ms = 20;
  /// Size the jitter buffer from the link as measured (drivers/rtp/jitter_budget.h: the spread
  /// of packet transit times and the retransmission round trip), between
  /// jitter_buffer_latency_ms and jitter_buffer_max_ms, starting at jitter_buffer_start_ms until
  /// 1 s of packets was seen. Off: jitter_buffer_latency_ms throughout.
  bool jitter_buffer_auto = true;
  int jitter_buffer_start_ms = 100;
  int jitter_buffer_max_ms = 300;
  /// Ask for a frame's missing last packet once its burst ended without the marker bit (after the
  /// measured reorder, at least 3 ms: drivers/rtp/frame_end_watch.h), instead of when the next
  /// frame shows the gap. Needs retransmission.
  bool frame_end_requests = true;
  bool retransmission = true;  ///< NACK (RTCP feedback) and RTX (RFC 4588) through rtpbin
  int payload_type = 96;       ///< the H.264 payload type (rtph264pay's default)
  int rtx_payload_type = 97;   ///< RTX payload type for `payload_type`
  /// ULP FEC from a sender that sends it (hybrid-remote --fec): behind the jitter buffer,
  /// rtpulpfecdec rebuilds a packet the jitter buffer gives up on from its frame's FEC packets,
  /// which rtpbin's rtpstorage keeps for as long as the jitter buffer may wait. A stream without
  /// FEC passes unchanged. Off: FEC packets are refused as another payload type.
  bool fec = true;
  int fec_payload_type = 122;
  /// The RTX payload type of a repaired FEC packet: a lost FEC packet is asked for like a media
  /// one, since the jitter buffer cannot tell them apart and its loss would cost a key frame.
  int rtx_fec_payload_type = 98;
  /// The RTCP bandwidth of the station's session, bytes/s (rtpsession rtcp-fraction; the
  /// default assumes a 64 kbit/s session, i.e. a receiver report every ~0.5 s). RFC 4585
  /// allows one early feedback packet per regular interval, so a NACK waits up to one interval:
  /// it must be well below the jitter buffer's latency for a retransmission to arrive in time.
  /// 20 000 B/s (3/4 of it for a receiver: a ~100-byte report every ~7 ms) is 4 % of a 4 Mbit/s
  /// stream, inside RFC 3550's 5 %.
  int rtcp_bandwidth_bytes_per_s = 20000;
  /// The jitter buffer asks for a missing packet this long after it was expected
  /// (rtpjitterbuffer rtx-delay), and at once when a packet this many sequence numbers later
  /// arrives (rtx-delay-reorder): with a 20 ms latency a request must leave within a few ms.
  int rtx_delay_ms = 1;
  int rtx_delay_reorder = 1;
  int64_t stall_timeout_ns = 500'000'000;  ///< no frame for this long: kStalled
  /// The most packets (in their time) waiting between the jitter buffer and the decoder, whose
  /// thread may wait for a CPU: the jitter buffer never waits for the decoder within it. 0.5 s,
  /// the stall timeout: video that far behind is shown as old anyway, and every packet is still
  /// needed, as each frame is a reference for the next.
  int decode_queue_ms = 500;
  /// The RTP socket's receive buffer, bytes (udpsrc buffer-size; 0: the system's default,
  /// net.core.rmem_default, 208 KiB on stock Linux). It holds what arrives while udpsrc's thread
  /// waits for a CPU; past it the kernel drops datagrams. A key frame comes as one burst: up to
  /// a few hundred KB at 720p from a sender without a VBV cap (x264's default), and on loopback
  /// within a millisecond; on top, the stream for as long as the thread may wait on a saturated
  /// machine, up to the stall timeout: 0.5 s of 4 Mbit/s is 250 KB. So ~0.6 MB of payload, which
  /// the kernel counts as whole skbs (~2.3 KB per 1.4 KB datagram: ~1 MB), and Linux grants
  /// twice what is asked for that bookkeeping: 2 MiB asked holds it twice over. Each camera has
  /// its own socket, so several cameras need no more each; the memory is only taken while
  /// datagrams wait. Above net.core.rmem_max udpsrc forces it (SO_RCVBUFFORCE: root or
  /// CAP_NET_ADMIN); otherwise the start report says what the system allows.
  int receive_buffer_bytes = 2 * 1024 * 1024;
  /// The RTCP socket's: a few ~100-byte reports a second, so any buffer holds seconds of them.
  /// 208 KiB is stock Linux's rmem_default and rmem_max: every process gets it without
  /// privilege, also on a host whose default was lowered.
  int rtcp_receive_buffer_bytes = 212992;
  /// Fault injection in the receive path (GStreamer netsim before rtpbin; tests and the faults
  /// table only): a packet is dropped with this probability, and delayed by a uniformly
  /// distributed min..max ms.
  double netsim_drop_probability = 0.0;
  int netsim_min_delay_ms = 0;
  int netsim_max_delay_ms = 0;
  /// A packet delayed less may overtake one delayed more (netsim allow-reordering); off, the
  /// delays vary as a queue's do, in order.
  bool netsim_reorder = false;
  /// With a key the stream must be SRTP (AES-128-GCM, media and RTCP): every packet that fails
  /// authentication (a wrong key, or a sender without encryption) is dropped and counted.
  std::optional<SrtpKey> srtp_key;
  /// netsim in the path even with no loss or delay (so a test can cut the link while running).
  bool netsim_always = false;
  /// How the sender's capture times (its CLOCK_REALTIME) reach this host's CLOCK_MONOTONIC:
  /// measured from its RTCP sender reports and round trip (ClockOffsetEstimator), or, when the
  /// sites declare synchronised clocks (chrony/PTP; station.yaml `clock: synchronized`), this
  /// host's CLOCK_REALTIME with their stated error (`clock_error_ms`) as the uncertainty.
  enum class Clock : uint8_t { kMeasured, kSynchronized };
  Clock clock = Clock::kMeasured;
  int64_t clock_error_ns = 1'000'000;
  double clock_drift_ppm = 100.0;  ///< allowed drift between the two clocks (measured mode)
  /// The shortest interval between this station's regular RTCP reports (rtpsession
  /// rtcp-min-interval; RFC 3550's Tmin, 5 s by default): each gives the sender a round trip,
  /// which the clock estimate needs, and lets one early feedback packet (a PLI) go. The RTCP
  /// bandwidth sets the interval above it: 50-80 ms measured. NACKs leave at once regardless
  /// (rtp_camera_nack.cpp).
  int rtcp_interval_ms = 20;
  bool netsim() const {
    return netsim_always || netsim_drop_probability > 0.0 || netsim_max_delay_ms > 0 ||
           netsim_min_delay_ms > 0;
  }
};

}  // namespace hd::drivers
