#pragma once
// The network camera's frame times: each frame's capture time on CLOCK_MONOTONIC (the sender's
// stamp through the clock mapping, or its arrival), the times it crossed the link's stages, and
// the "never older than the last one shown" rule. Plain data in, plain data out: no GStreamer.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/clock_offset_estimator.h"
#include "drivers/rtp/rtp_frame_stamp.h"
#include "drivers/rtp/rtp_receive_config.h"

namespace hd::drivers {

/// What one frame's packets and the decoder said of it, kept by the frame's buffer PTS (the
/// depayloader's input, after the jitter buffer, to the decoded frame: the decoder keeps PTS).
/// Times are CLOCK_MONOTONIC ns; 0 = not known.
struct RtpFrameStages {
  uint64_t pts = ~0ull;
  int64_t capture_mono_ns = 0;          ///< the sender's stamp, mapped (0: unstamped)
  int64_t encoded_ns = 0, sent_ns = 0;  ///< capture + the sender-stages offsets (0: none)
  int64_t received_ns = 0;              ///< its last packet at the depayloader
  int64_t arrival_ns = 0;               ///< udpsrc's stamp of its earliest packet
  int64_t uncertainty_ns = -1;          ///< of capture_mono_ns (-1 unknown)
  int64_t decoded_ns = 0;
  bool has_revision = false;  ///< the packets carried a camera-state (calibration revision)
  uint32_t revision = 0;
};

/// The times of one decoded frame as it would be published.
struct RtpStampedFrame {
  RtpFrameStages stages;
  /// The sender's capture time is known: capture_ns is it, mapped (or the arrival, when the
  /// mapping put it after the arrival). Unstamped: capture_ns = arrival_ns.
  bool stamped = false;
  int64_t capture_ns = 0;
  /// udpsrc's stamp of the frame's earliest packet; without one (a frame of retransmissions
  /// only), when its last packet reached the depayloader; without that, the decoded frame's time.
  int64_t arrival_ns = 0;
  /// The mapped capture time lay after the arrival (the clocks disagree): replaced by it.
  bool capture_after_arrival = false;
};

/// Threads: note_arrival is udpsrc's (or srtpdec's), arrival_of and add_packet the depayloader's,
/// add_sender_report the RTCP source's, add_decoded the decoder's, frame() and admit() the
/// appsink's; clock_mapping() and capture_of() any. One mutex guards the frame slots, one the
/// clock estimate; the arrivals are one atomic each (the hot path takes no lock for them).
class RtpFrameStamper {
 public:
  static constexpr std::size_t kSlots = 16;  ///< frames in flight at most (a few)
  /// Packets whose arrival is remembered (by sequence number modulo kArrivals).
  static constexpr std::size_t kArrivals = 1024;
  /// An arrival older than this is of an earlier round of the 16-bit sequence numbers (or of a
  /// renumbered stream).
  static constexpr int64_t kArrivalMaxAgeNs = 1'000'000'000;
  using HostOffset = int64_t (*)();

  /// `host_offset` reads CLOCK_REALTIME - CLOCK_MONOTONIC (tests pass a fixed one).
  explicit RtpFrameStamper(const RtpReceiveConfig& config,
                           HostOffset host_offset = &realtime_minus_monotonic_ns);

  /// A media packet passed on to rtpbin, with udpsrc's arrival stamp (mono ns).
  void note_arrival(uint16_t sequence, int64_t arrival_ns);
  /// That packet's arrival, rounded down to the microsecond (so never after udpsrc stamped it);
  /// 0 when not known (never noted, overwritten, older than kArrivalMaxAgeNs, after `now_ns`).
  int64_t arrival_of(uint16_t sequence, int64_t now_ns) const;

  /// An RTCP sender report: the sender's NTP time (Unix ns) and its arrival (mono ns).
  void add_sender_report(int64_t sender_unix_ns, int64_t arrival_mono_ns);
  /// A packet at the depayloader at `now_ns`: `pts` its buffer time (nullopt: none, the packet
  /// only feeds the clock), `stamp` what its header extensions said (null: no valid stamp).
  /// Each packet's arrival joins its frame's; each stamp replaces the frame's earlier ones (the
  /// frame was sent with its last packet); a new round trip in it goes to the clock estimate, and
  /// a stamp with an arrival bounds the measured offset (ClockOffsetEstimator::add_packet).
  void add_packet(std::optional<uint64_t> pts, uint16_t sequence, const RtpFrameStamp* stamp,
                  int64_t now_ns);
  /// The decoder put out the frame of `pts` at `now_ns`.
  void add_decoded(uint64_t pts, int64_t now_ns);
  /// The mapped capture time of the frame of `pts` (0: unknown or unstamped).
  int64_t capture_of(uint64_t pts) const;

  /// The decoded frame of `pts` (nullopt: it has none) at `now_ns`, as it would be published.
  RtpStampedFrame frame(std::optional<uint64_t> pts, int64_t now_ns) const;
  /// Whether `f` is newer than the last frame admitted (its capture_ns later): only then is it
  /// published, and it becomes the last one. Old video is never presented as new.
  bool admit(const RtpStampedFrame& f);

  /// The sender-clock mapping at `now_ns`: measured once there are a sender report and a round
  /// trip, this host's offset before (exact on one host only), or the synchronized clocks'.
  ClockMapping clock_mapping(int64_t now_ns) const;

 private:
  // The synchronized clocks' mapping, or `measured` with this host's offset while unmeasured.
  ClockMapping resolved(const ClockMapping& measured) const;
  // Finds or makes the slot of `pts` (under slots_mutex_) and notes a packet's arrival in it.
  RtpFrameStages& slot(uint64_t pts, int64_t arrival_ns, int64_t now_ns);

  RtpReceiveConfig::Clock clock_kind_;
  int64_t clock_error_ns_;
  HostOffset host_offset_;
  // (arrival in us << 16) | sequence: one store (udpsrc's thread), one load (the jitter
  // buffer's, which replaces the buffer's times with its own estimate). 48 bits of
  // microseconds last 8 years.
  std::array<std::atomic<uint64_t>, kArrivals> arrivals_{};
  mutable std::mutex clock_mutex_;
  ClockOffsetEstimator clock_;
  uint8_t last_round_trip_count_ = 0;  // depayloader thread
  mutable std::mutex slots_mutex_;
  std::array<RtpFrameStages, kSlots> slots_{};
  std::size_t next_slot_ = 0;
  int64_t last_admitted_ns_ = 0;  // appsink thread
};

}  // namespace hd::drivers
