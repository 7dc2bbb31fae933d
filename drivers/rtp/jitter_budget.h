#pragma once
// How long the station's jitter buffer must hold packets for this link, and how long a gap must
// last before it is a loss: sized from what the link measurably does instead of a fixed guess.
// A pure value type; the camera feeds it every packet where it enters rtpbin and applies it.
//
// Transit: arrival (CLOCK_MONOTONIC ns) minus the packet's RTP time (90 kHz, unwrapped, in ns).
// Its absolute value is meaningless (two clocks); its spread is what the jitter buffer must
// absorb: the sender's capture-to-send variation, the network's jitter and this host's scheduling
// delay alike. Reorder: how long a packet that came after a later one had been missing (the
// arrival of its successor to its own), 0 on a link that keeps the order (a queue's delay varies,
// its order does not): a gap shorter than that may be a packet on its way, and asking for it
// would only bring a duplicate.
//
// The budget: a packet is due at the earliest transit plus the latency, so the latency covers the
// latest packet still of use. Originals: their spread. With retransmission, a repair: its
// original's lateness, the wait before asking (1.5 x reorder, at least request_wait_ms) and the
// round trip; and the repairs' own lateness: measured (a retransmission carries its original's
// RTP time) once repairs came, with room for one more request should a repair be lost (the wait,
// the round trip and the link's burst pause again); until then the originals' spread again. A
// quarter of the spread and a margin on top, for what the window has not seen yet. Clamped to
// [min_ms, max_ms]: min keeps an idle link's latency where it was; max bounds what a broken link
// costs (older video is marked old anyway).
//
// The window: kBuckets buckets of kBucketNs (2 s), so the budget follows the link up within one
// packet and down within 2 s.
#include <array>
#include <cstdint>

namespace hd::drivers {

class JitterBudget {
 public:
  struct Settings {
    int min_ms = 20;
    int max_ms = 300;
    int start_ms = 100;  ///< until kWarmUpNs of packets were seen
    bool retransmission = true;
    int request_wait_ms = 3;  ///< the least wait before a gap is asked for
    int round_trip_ms = 2;    ///< until the jitter buffer measured one: a LAN's, on a busy host
    int margin_ms = 5;
  };
  static constexpr int kBuckets = 8;
  static constexpr int64_t kBucketNs = 250'000'000;
  static constexpr int64_t kWarmUpNs = 1'000'000'000;
  static constexpr int64_t kRtpClockHz = 90'000;

  explicit JitterBudget(Settings s) : s_(s) {}

  /// One media packet (any order), or the repair of one (`repair`: a retransmission).
  void add_packet(uint32_t rtp_time, uint16_t sequence, int64_t arrival_ns, bool repair = false);
  /// The measured retransmission round trip (rtpjitterbuffer's rtx-rtt), ns; <= 0: not known.
  void set_round_trip(int64_t round_trip_ns) { round_trip_ns_ = round_trip_ns; }

  /// Largest minus smallest transit of the originals in the window, ns.
  int64_t spread_ns() const;
  /// Latest repair's transit minus the originals' smallest, ns (0: no repair in the window).
  int64_t repair_spread_ns() const;
  /// The longest a reordered packet was missing in the window, ns (0: the link keeps the order).
  int64_t reorder_ns() const;
  int64_t round_trip_ns() const { return round_trip_ns_ > 0 ? round_trip_ns_ : 0; }
  /// How long a gap lasts before it is asked for, ns: reorder_ns(), at least request_wait_ms.
  int64_t request_wait_ns() const;
  /// The longest pause between two consecutive packets of one frame in the window, ns: a
  /// frame's burst may pause this long and go on (a queue's jitter spreads it out).
  int64_t burst_gap_ns() const;
  /// How long after a frame's newest packet its missing end is asked for, ns: 1.5 x
  /// burst_gap_ns(), at least request_wait_ms (FrameEndWatch).
  int64_t frame_end_wait_ns() const;
  /// The latency the jitter buffer needs now, ms (start_ms during the warm-up).
  int latency_ms() const;
  bool warmed_up() const { return seen_ns_ >= kWarmUpNs; }
  const Settings& settings() const { return s_; }

 private:
  struct Bucket {
    int64_t start_ns = 0;
    int64_t min = 0, max = 0;  // the originals' transit
    int64_t repair_max = 0;
    int64_t reorder = 0, burst_gap = 0;
    bool used = false, originals = false, repaired = false;
  };
  struct Window {
    int64_t lo = 0, hi = 0, repair_hi = 0, reorder = 0, burst_gap = 0;
    bool originals = false, repaired = false;
  };
  Window window() const;
  Bucket& bucket_at(int64_t arrival_ns);

  Settings s_;
  std::array<Bucket, kBuckets> buckets_{};
  bool started_ = false;
  uint32_t last_rtp_ = 0;
  int64_t rtp_unwrapped_ = 0;  // in 90 kHz ticks since the first packet
  int64_t first_ns_ = 0, seen_ns_ = 0;
  int64_t round_trip_ns_ = 0;
  // Arrival of the newest packets by sequence number (modulo the array), for reorder_ns().
  std::array<int64_t, 1024> arrivals_{};
  uint16_t highest_seq_ = 0;
  uint32_t highest_rtp_ = 0;  // the RTP time of the highest packet
};

}  // namespace hd::drivers
