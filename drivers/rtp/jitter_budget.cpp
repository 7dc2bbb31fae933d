#include "drivers/rtp/jitter_budget.h"

#include <algorithm>

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;

}  // namespace

JitterBudget::Bucket& JitterBudget::bucket_at(int64_t arrival_ns) {
  const int64_t start = arrival_ns - arrival_ns % kBucketNs;
  Bucket& b = buckets_[static_cast<std::size_t>((arrival_ns / kBucketNs) % kBuckets)];
  if (!b.used || b.start_ns != start) b = Bucket{start, 0, 0, 0, 0, 0, true, false, false};
  return b;
}

void JitterBudget::add_packet(uint32_t rtp_time, uint16_t sequence, int64_t arrival_ns,
                              bool repair) {
  if (!started_) {
    started_ = true;
    last_rtp_ = rtp_time;
    first_ns_ = arrival_ns;
    highest_seq_ = static_cast<uint16_t>(sequence - 1);
  }
  // Unwrapped relative to the newest: a repair or a reordered packet lies behind it.
  const int32_t step = static_cast<int32_t>(rtp_time - last_rtp_);
  const int64_t ticks = rtp_unwrapped_ + step;
  if (step > 0) {
    rtp_unwrapped_ = ticks;
    last_rtp_ = rtp_time;
  }
  seen_ns_ = std::max(seen_ns_, arrival_ns - first_ns_);
  const int64_t transit = arrival_ns - ticks * 1'000'000'000 / kRtpClockHz;
  Bucket& b = bucket_at(arrival_ns);
  if (repair) {
    b.repair_max = b.repaired ? std::max(b.repair_max, transit) : transit;
    b.repaired = true;
    return;
  }
  b.min = b.originals ? std::min(b.min, transit) : transit;
  b.max = b.originals ? std::max(b.max, transit) : transit;
  b.originals = true;
  const int16_t ahead = static_cast<int16_t>(sequence - highest_seq_);
  if (ahead == 1 && rtp_time == highest_rtp_) {  // the next packet of the same frame
    const int64_t t = arrivals_[highest_seq_ % arrivals_.size()];
    if (t != 0) b.burst_gap = std::max(b.burst_gap, arrival_ns - t);
  }
  if (ahead > 0) {
    highest_rtp_ = rtp_time;
    // Packets skipped over are not here yet: their slots must not keep an older round's times.
    for (int16_t i = 1; i < ahead && i < int16_t(arrivals_.size()); ++i)
      arrivals_[static_cast<uint16_t>(highest_seq_ + i) % arrivals_.size()] = 0;
    highest_seq_ = sequence;
  } else if (-ahead < int16_t(arrivals_.size())) {
    // Came after a later packet: missing since its successor came (or the next one that did).
    for (uint16_t next = static_cast<uint16_t>(sequence + 1);
         static_cast<int16_t>(highest_seq_ - next) >= 0; ++next) {
      const int64_t t = arrivals_[next % arrivals_.size()];
      if (t == 0) continue;
      b.reorder = std::max(b.reorder, arrival_ns - t);
      break;
    }
  }
  arrivals_[sequence % arrivals_.size()] = arrival_ns;
}

JitterBudget::Window JitterBudget::window() const {
  int64_t newest = 0;
  for (const Bucket& b : buckets_)
    if (b.used) newest = std::max(newest, b.start_ns);
  Window w;
  for (const Bucket& b : buckets_) {
    if (!b.used || b.start_ns <= newest - kBuckets * kBucketNs) continue;  // out of the window
    if (b.repaired) {
      w.repair_hi = w.repaired ? std::max(w.repair_hi, b.repair_max) : b.repair_max;
      w.repaired = true;
    }
    if (!b.originals) continue;
    w.lo = w.originals ? std::min(w.lo, b.min) : b.min;
    w.hi = w.originals ? std::max(w.hi, b.max) : b.max;
    w.reorder = std::max(w.reorder, b.reorder);
    w.burst_gap = std::max(w.burst_gap, b.burst_gap);
    w.originals = true;
  }
  return w;
}

int64_t JitterBudget::spread_ns() const {
  const Window w = window();
  return w.originals ? w.hi - w.lo : 0;
}

int64_t JitterBudget::repair_spread_ns() const {
  const Window w = window();
  return w.originals && w.repaired ? std::max<int64_t>(0, w.repair_hi - w.lo) : 0;
}

int64_t JitterBudget::reorder_ns() const {
  return window().reorder;
}

int64_t JitterBudget::request_wait_ns() const {
  return std::max(reorder_ns(), s_.request_wait_ms * kMs);
}

int64_t JitterBudget::burst_gap_ns() const {
  return window().burst_gap;
}

int64_t JitterBudget::frame_end_wait_ns() const {
  return std::max(burst_gap_ns() * 3 / 2, s_.request_wait_ms * kMs);
}

int JitterBudget::latency_ms() const {
  if (!warmed_up()) return std::clamp(s_.start_ms, s_.min_ms, s_.max_ms);
  const Window w = window();
  const int64_t spread = w.originals ? w.hi - w.lo : 0;
  int64_t need = spread;
  if (s_.retransmission) {
    const int64_t round_trip = round_trip_ns() > 0 ? round_trip_ns() : s_.round_trip_ms * kMs;
    const int64_t wait = std::max(w.reorder * 3 / 2, s_.request_wait_ms * kMs);
    const int64_t asked = spread + wait + round_trip;
    // A repair may itself be lost: room for one more request, one round trip, wait and burst
    // pause (the repair's own jitter) after the latest repair seen.
    const int64_t repaired = w.repair_hi - w.lo + wait + round_trip + w.burst_gap;
    need = std::max({need, asked, w.repaired ? repaired : asked + spread});
  }
  // The window saw at most its own worst: a quarter of the spread on top (a busy host's delays
  // grow in bursts), and the margin.
  need += spread / 4 + s_.margin_ms * kMs;
  return static_cast<int>(std::clamp<int64_t>((need + kMs - 1) / kMs, s_.min_ms, s_.max_ms));
}

}  // namespace hd::drivers
