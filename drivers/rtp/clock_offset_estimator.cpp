#include "drivers/rtp/clock_offset_estimator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "drivers/rtp/rtp_frame_stamp.h"

namespace hd::drivers {

const char* to_string(ClockMapping::Kind k) {
  switch (k) {
    case ClockMapping::Kind::kUnmeasured:
      return "unmeasured (this host's CLOCK_REALTIME: exact on one host only)";
    case ClockMapping::Kind::kMeasured:
      return "measured (RTCP sender reports and the sender's round trip)";
    case ClockMapping::Kind::kSynchronized:
      return "synchronized (CLOCK_REALTIME of both sites, stated error)";
  }
  return "unknown";
}

int64_t sites_offset_ns(const ClockMapping& m, int64_t realtime_minus_monotonic_ns) {
  // station mono = sender unix + offset, station unix = station mono + realtime_minus_monotonic.
  return -(m.offset_ns + realtime_minus_monotonic_ns);
}

std::string describe(const ClockMapping& m, int64_t realtime_minus_monotonic_ns) {
  double sites_ms = double(sites_offset_ns(m, realtime_minus_monotonic_ns)) * 1e-6;
  if (std::fabs(sites_ms) < 0.0005) sites_ms = 0.0;  // printed as +0.000, never -0.000
  const double error_ms = double(m.uncertainty_ns) * 1e-6;
  char text[320];
  switch (m.kind) {
    case ClockMapping::Kind::kUnmeasured:
      return "not measured yet (no RTCP sender report and round trip): the sender's capture "
             "stamps are read as this host's CLOCK_REALTIME, right only on one host";
    case ClockMapping::Kind::kMeasured:
      std::snprintf(text, sizeof text,
                    "sender's CLOCK_REALTIME - this station's = %+.3f ms +- %.3f ms, measured "
                    "from %llu RTCP sender reports and round trips (smallest round trip "
                    "%.3f ms)%s",
                    sites_ms, error_ms, static_cast<unsigned long long>(m.samples),
                    double(m.round_trip_ns) * 1e-6,
                    m.bounded_by_packets ? ", capped by the media packets' arrival" : "");
      return text;
    case ClockMapping::Kind::kSynchronized:
      std::snprintf(text, sizeof text,
                    "both sites' CLOCK_REALTIME declared synchronized (chrony/PTP, or one host): "
                    "sender's - this station's = %+.3f ms +- %.3f ms as stated, not measured",
                    sites_ms, error_ms);
      return text;
  }
  return "unknown";
}

void ClockOffsetEstimator::add_sender_report(int64_t sender_unix_ns, int64_t arrival_mono_ns) {
  if (report_count_ > 0 && arrival_mono_ns < newest_arrival_ns_) {
    ++refused_;
    return;
  }
  newest_arrival_ns_ = arrival_mono_ns;
  reports_[report_next_] = {arrival_mono_ns - sender_unix_ns, arrival_mono_ns};
  report_next_ = (report_next_ + 1) % kWindow;
  report_count_ = std::min(report_count_ + 1, kWindow);
  ++samples_;
}

void ClockOffsetEstimator::add_round_trip(int64_t round_trip_ns) {
  if (round_trip_ns < 0) {
    ++refused_;
    return;
  }
  round_trips_[round_trip_next_] = round_trip_ns;
  round_trip_next_ = (round_trip_next_ + 1) % kWindow;
  round_trip_count_ = std::min(round_trip_count_ + 1, kWindow);
  ++samples_;
}

void ClockOffsetEstimator::add_packet(int64_t capture_unix_ns, int64_t arrival_mono_ns) {
  if (arrival_mono_ns - bound_span_start_ns_ >= kBoundSpanNs) {
    // A new span; the current one becomes the previous, unless it is over two spans old.
    previous_bound_ns_ =
        arrival_mono_ns - bound_span_start_ns_ >= 2 * kBoundSpanNs ? kNoBound : bound_ns_;
    bound_ns_ = kNoBound;
    bound_span_start_ns_ = arrival_mono_ns;
  }
  bound_ns_ = std::min(bound_ns_, arrival_mono_ns - capture_unix_ns);
}

ClockMapping ClockOffsetEstimator::mapping(int64_t now_mono_ns) const {
  ClockMapping m;
  m.samples = samples_;
  if (round_trip_count_ > 0)
    m.round_trip_ns = *std::min_element(round_trips_.begin(),
                                        round_trips_.begin() + std::ptrdiff_t(round_trip_count_));
  if (report_count_ == 0 || round_trip_count_ == 0) return m;
  const Report* best = &reports_[0];
  for (std::size_t i = 1; i < report_count_; ++i)
    if (reports_[i].difference_ns < best->difference_ns) best = &reports_[i];
  const int64_t half = m.round_trip_ns / 2;
  const int64_t age_ns = std::max<int64_t>(0, now_mono_ns - best->arrival_mono_ns);
  const auto drift_ns = static_cast<int64_t>(double(age_ns) * drift_ppm_ * 1e-6);
  m.kind = ClockMapping::Kind::kMeasured;
  m.offset_ns = best->difference_ns - half;
  // R/2 rounded up, so that an odd round trip still bounds the error.
  m.uncertainty_ns = m.round_trip_ns - half + drift_ns;
  // The spans as they stand at `now_mono_ns`: a bound over two spans old is dropped.
  const int64_t span_age_ns = now_mono_ns - bound_span_start_ns_;
  const int64_t bound = span_age_ns >= 2 * kBoundSpanNs ? kNoBound
                        : span_age_ns >= kBoundSpanNs   ? bound_ns_
                                                        : std::min(bound_ns_, previous_bound_ns_);
  if (bound < m.offset_ns) {
    // The bound may have drifted for up to two spans, towards either side.
    m.uncertainty_ns +=
        m.offset_ns - bound + static_cast<int64_t>(double(2 * kBoundSpanNs) * drift_ppm_ * 1e-6);
    m.offset_ns = bound;
    m.bounded_by_packets = true;
  }
  return m;
}

int64_t round_trip_from_report_block(uint32_t arrival_compact, uint32_t lsr, uint32_t dlsr) {
  if (lsr == 0) return -1;
  const auto rtt = static_cast<int32_t>(arrival_compact - lsr - dlsr);
  if (rtt < 0) return -1;
  // 1/65536 s units, to ns (rounded).
  return (int64_t(rtt) * 1'000'000'000LL + (1LL << 15)) >> 16;
}

uint32_t compact_ntp(int64_t unix_ns) {
  return static_cast<uint32_t>(unix_ns_to_ntp64(unix_ns) >> 16);
}

}  // namespace hd::drivers
