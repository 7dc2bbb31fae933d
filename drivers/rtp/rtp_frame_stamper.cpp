// RtpFrameStamper: frame slots by PTS, the arrivals ring, the clock mapping, the publish rule.
#include "drivers/rtp/rtp_frame_stamper.h"

#include <time.h>

#include <algorithm>

namespace hd::drivers {

RtpFrameStamper::RtpFrameStamper(const RtpReceiveConfig& config, HostOffset host_offset)
    : clock_kind_(config.clock),
      clock_error_ns_(config.clock_error_ns),
      host_offset_(host_offset),
      clock_(config.clock_drift_ppm) {}

void RtpFrameStamper::note_arrival(uint16_t sequence, int64_t arrival_ns) {
  const uint64_t us = arrival_ns > 0 ? uint64_t(arrival_ns) / 1000 : 0;
  arrivals_[sequence % kArrivals].store((us << 16) | sequence, std::memory_order_relaxed);
}

int64_t RtpFrameStamper::arrival_of(uint16_t sequence, int64_t now_ns) const {
  const uint64_t v = arrivals_[sequence % kArrivals].load(std::memory_order_relaxed);
  if (v == 0 || uint16_t(v & 0xFFFF) != sequence) return 0;
  const int64_t arrival = int64_t(v >> 16) * 1000;
  return arrival <= now_ns && now_ns - arrival < kArrivalMaxAgeNs ? arrival : 0;
}

void RtpFrameStamper::add_sender_report(int64_t sender_unix_ns, int64_t arrival_mono_ns) {
  std::lock_guard lock(clock_mutex_);
  clock_.add_sender_report(sender_unix_ns, arrival_mono_ns);
}

ClockMapping RtpFrameStamper::resolved(const ClockMapping& measured) const {
  ClockMapping m = measured;
  if (clock_kind_ == RtpReceiveConfig::Clock::kSynchronized) {
    m = ClockMapping{};
    m.kind = ClockMapping::Kind::kSynchronized;
    m.offset_ns = -host_offset_();
    m.uncertainty_ns = clock_error_ns_;
  } else if (m.kind == ClockMapping::Kind::kUnmeasured) {
    m.offset_ns = -host_offset_();
  }
  return m;
}

ClockMapping RtpFrameStamper::clock_mapping(int64_t now_ns) const {
  if (clock_kind_ == RtpReceiveConfig::Clock::kSynchronized) return resolved(ClockMapping{});
  std::lock_guard lock(clock_mutex_);
  return resolved(clock_.mapping(now_ns));
}

RtpFrameStages& RtpFrameStamper::slot(uint64_t pts, int64_t arrival_ns, int64_t now_ns) {
  for (RtpFrameStages& s : slots_)
    if (s.pts == pts) {  // a later packet of the frame (in the jitter buffer's order)
      if (arrival_ns != 0 && (s.arrival_ns == 0 || arrival_ns < s.arrival_ns))
        s.arrival_ns = arrival_ns;
      // Received when its last packet is through, as "sent" is its last packet's: the first
      // packet may be through before the last was even sent.
      s.received_ns = std::max(s.received_ns, now_ns);
      return s;
    }
  RtpFrameStages& s = slots_[next_slot_];
  next_slot_ = (next_slot_ + 1) % kSlots;
  s = {};
  s.pts = pts;
  s.received_ns = now_ns;
  s.arrival_ns = arrival_ns;
  return s;
}

void RtpFrameStamper::add_packet(std::optional<uint64_t> pts, uint16_t sequence,
                                 const RtpFrameStamp* stamp, int64_t now_ns) {
  if (stamp != nullptr && stamp->stages && stamp->stages->round_trip_count != 0 &&
      stamp->stages->round_trip_count != last_round_trip_count_) {  // a new round trip
    last_round_trip_count_ = stamp->stages->round_trip_count;
    std::lock_guard lock(clock_mutex_);
    clock_.add_round_trip(int64_t(stamp->stages->round_trip_us) * 1000);
  }
  if (!pts) return;
  const int64_t arrival = arrival_of(sequence, now_ns);
  const bool stamped = stamp != nullptr && stamp->capture_unix_ns.has_value();
  ClockMapping m;
  if (stamped && clock_kind_ == RtpReceiveConfig::Clock::kMeasured) {
    // One lock per packet: its bound goes in and the mapping it gets comes out together.
    std::lock_guard lock(clock_mutex_);
    if (arrival != 0) clock_.add_packet(*stamp->capture_unix_ns, arrival);
    m = resolved(clock_.mapping(now_ns));
  } else if (stamped) {
    m = resolved(ClockMapping{});
  }
  std::lock_guard lock(slots_mutex_);
  RtpFrameStages& s = slot(*pts, arrival, now_ns);  // every packet: when its frame came in
  if (!stamped) return;
  s.capture_mono_ns = *stamp->capture_unix_ns + m.offset_ns;
  if (stamp->stages) {
    s.encoded_ns = s.capture_mono_ns + int64_t(stamp->stages->encoded_us) * 1000;
    s.sent_ns = std::max(s.sent_ns, s.capture_mono_ns + int64_t(stamp->stages->sent_us) * 1000);
  } else {
    s.encoded_ns = 0;
  }
  s.uncertainty_ns = m.uncertainty_ns;
  s.has_revision = stamp->camera.has_value();
  s.revision = s.has_revision ? stamp->camera->calibration_revision : 0;
}

void RtpFrameStamper::add_decoded(uint64_t pts, int64_t now_ns) {
  std::lock_guard lock(slots_mutex_);
  for (RtpFrameStages& s : slots_)
    if (s.pts == pts) {
      s.decoded_ns = now_ns;
      return;
    }
  // A frame whose packets left no slot (gone from the ring): one for its decode time only.
  RtpFrameStages& s = slots_[next_slot_];
  next_slot_ = (next_slot_ + 1) % kSlots;
  s = {};
  s.pts = pts;
  s.decoded_ns = now_ns;
}

int64_t RtpFrameStamper::capture_of(uint64_t pts) const {
  int64_t capture = 0;
  std::lock_guard lock(slots_mutex_);
  for (const RtpFrameStages& s : slots_)
    if (s.pts == pts) capture = s.capture_mono_ns;
  return capture;
}

RtpStampedFrame RtpFrameStamper::frame(std::optional<uint64_t> pts, int64_t now_ns) const {
  RtpStampedFrame f;
  if (pts) {
    std::lock_guard lock(slots_mutex_);
    for (const RtpFrameStages& s : slots_)
      if (s.pts == *pts) f.stages = s;
  }
  // Not the buffer's PTS: the jitter buffer's skew-smoothed output time may lie after the frame
  // was even decoded (a capture or decode time before "arrival" was seen under load).
  f.arrival_ns = now_ns;
  if (f.stages.arrival_ns != 0 && f.stages.arrival_ns <= now_ns)
    f.arrival_ns = f.stages.arrival_ns;
  else if (f.stages.received_ns != 0 && f.stages.received_ns <= now_ns)
    f.arrival_ns = f.stages.received_ns;
  f.stamped = f.stages.capture_mono_ns != 0;
  f.capture_ns = f.stamped ? f.stages.capture_mono_ns : f.arrival_ns;
  if (f.stamped && f.capture_ns > f.arrival_ns) {  // impossible: the clocks disagree
    f.capture_after_arrival = true;
    f.capture_ns = f.arrival_ns;
  }
  return f;
}

bool RtpFrameStamper::admit(const RtpStampedFrame& f) {
  if (f.capture_ns <= last_admitted_ns_) return false;
  last_admitted_ns_ = f.capture_ns;
  return true;
}

}  // namespace hd::drivers
