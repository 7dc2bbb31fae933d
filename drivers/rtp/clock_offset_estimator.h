#pragma once
// The offset between a sender's clock and this station's CLOCK_MONOTONIC, measured from RTCP
// sender reports and the round trip (NTP-style), with its uncertainty; a pure value type.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace hd::drivers {

/// The mapping of a sender's capture time (its CLOCK_REALTIME, Unix ns) onto this host's
/// CLOCK_MONOTONIC: `station_mono_ns = sender_unix_ns + offset_ns`, true to within
/// ±uncertainty_ns.
struct ClockMapping {
  enum class Kind : uint8_t {
    /// Not measured yet (no sender report, or no round trip): this host's own
    /// CLOCK_REALTIME - CLOCK_MONOTONIC, exact only when both programs run on one host.
    kUnmeasured,
    /// From RTCP sender reports and the sender's round trip (ClockOffsetEstimator).
    kMeasured,
    /// The sites declared synchronised clocks (chrony/PTP): this host's CLOCK_REALTIME, with
    /// their stated error as the uncertainty.
    kSynchronized,
  };
  Kind kind = Kind::kUnmeasured;
  int64_t offset_ns = 0;
  int64_t uncertainty_ns = -1;  ///< -1: unknown
  uint64_t samples = 0;         ///< sender reports and round trips taken into the estimate
  int64_t round_trip_ns = -1;   ///< the smallest round trip in the window (-1 none)
  /// The media packets' bound (see ClockOffsetEstimator) lay below the sender reports'
  /// estimate and replaced it: the reports were delayed more than their round trip says.
  bool bounded_by_packets = false;
};
const char* to_string(ClockMapping::Kind k);
/// The mapping in words a user can check: which clocks, the offset between the two sites'
/// CLOCK_REALTIME (not between two clocks of this host: `realtime_minus_monotonic_ns` is this
/// host's), its uncertainty, and how it was measured.
std::string describe(const ClockMapping& m, int64_t realtime_minus_monotonic_ns);
/// The sender's CLOCK_REALTIME minus this host's, by the mapping.
int64_t sites_offset_ns(const ClockMapping& m, int64_t realtime_minus_monotonic_ns);

/// NTP's clock filter on RTCP: each sender report gives `arrival - sent = offset + d`, with d the
/// one-way delay, 0 <= d <= the round trip. Over the newest kWindow reports the one with the
/// smallest `arrival - sent` has the least queueing; with the smallest round trip R of the
/// window the offset is `min(arrival - sent) - R / 2`, within ±R / 2 (whatever way the delay
/// splits), plus the clocks' drift since that report (drift_ppm of its age; crystals drift
/// 10-50 ppm, 100 by default). A report whose arrival is older than the newest one already
/// taken is refused (counted).
///
/// The reports alone fail when a busy machine delays them longer than the smallest round trip
/// of the window (seen under load on one host: mapped captures up to tens of ms after their
/// packets arrived). Every stamped media packet bounds the offset from above, as its capture
/// precedes its arrival: `offset <= arrival - capture`. The smallest such difference of the
/// last one to two seconds (kBoundSpanNs; older ones may have drifted) caps the estimate. When it
/// does, the reports were off by at least the gap, and the uncertainty grows by it.
class ClockOffsetEstimator {
 public:
  static constexpr std::size_t kWindow = 8;
  /// The packets' bound is kept per span of this length, the current and the previous one.
  static constexpr int64_t kBoundSpanNs = 1'000'000'000;

  explicit ClockOffsetEstimator(double drift_ppm = 100.0) : drift_ppm_(drift_ppm) {}

  /// A sender report: its NTP time (sender's clock, Unix ns) and its arrival here (mono ns).
  void add_sender_report(int64_t sender_unix_ns, int64_t arrival_mono_ns);
  /// A round trip the sender measured from this station's receiver reports (RFC 3550 A.8).
  void add_round_trip(int64_t round_trip_ns);
  /// A stamped media packet: its capture (sender's clock, Unix ns) and its arrival here (mono
  /// ns, the socket's stamp). Not a sample: it only bounds the offset from above.
  void add_packet(int64_t capture_unix_ns, int64_t arrival_mono_ns);

  /// The estimate at `now_mono_ns` (for the drift allowance); kUnmeasured until there is at
  /// least one sender report and one round trip.
  ClockMapping mapping(int64_t now_mono_ns) const;
  uint64_t refused() const { return refused_; }

 private:
  struct Report {
    int64_t difference_ns = 0;  // arrival - sent
    int64_t arrival_mono_ns = 0;
  };
  double drift_ppm_;
  std::array<Report, kWindow> reports_{};
  std::array<int64_t, kWindow> round_trips_{};
  std::size_t report_count_ = 0, report_next_ = 0;
  std::size_t round_trip_count_ = 0, round_trip_next_ = 0;
  uint64_t samples_ = 0, refused_ = 0;
  int64_t newest_arrival_ns_ = 0;
  // The smallest arrival - capture of the current span and of the previous one (kNoBound: none).
  static constexpr int64_t kNoBound = INT64_MAX;
  int64_t bound_ns_ = kNoBound, previous_bound_ns_ = kNoBound, bound_span_start_ns_ = 0;
};

/// RFC 3550 A.8: the round trip from a receiver report block, in ns: `arrival - LSR - DLSR`,
/// all in the compact NTP format (the middle 32 bits: 1/65536 s), `arrival_compact` on the
/// clock whose sender reports the block refers to. -1 when the block has no LSR (no sender
/// report reached the receiver yet) or the result is negative (a clock step).
int64_t round_trip_from_report_block(uint32_t arrival_compact, uint32_t lsr, uint32_t dlsr);
/// The compact NTP form (middle 32 bits) of a Unix time.
uint32_t compact_ntp(int64_t unix_ns);

}  // namespace hd::drivers
