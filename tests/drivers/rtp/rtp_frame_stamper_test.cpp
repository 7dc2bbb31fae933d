// RtpFrameStamper with synthetic packets and a fixed host clock offset: each frame's arrival,
// stages and capture time against closed forms, the clock mapping in its three kinds, and the
// "never older than the last one" rule.
#include "drivers/rtp/rtp_frame_stamper.h"

#include <gtest/gtest.h>

namespace hd::drivers {
namespace {

constexpr int64_t kMs = 1'000'000;
// This host's CLOCK_REALTIME - CLOCK_MONOTONIC, fixed for the tests.
constexpr int64_t kHostOffset = 1'700'000'000'000'000'000LL;
int64_t host_offset() {
  return kHostOffset;
}

RtpReceiveConfig synchronized(int64_t error_ns) {
  RtpReceiveConfig c;
  c.clock = RtpReceiveConfig::Clock::kSynchronized;
  c.clock_error_ns = error_ns;
  return c;
}

RtpReceiveConfig measured() {
  RtpReceiveConfig c;
  c.clock_drift_ppm = 0.0;  // no drift allowance: the uncertainty is the round trip's half
  return c;
}

// A stamp whose capture lies at `capture_mono_ns` on this host through the synchronized clock.
RtpFrameStamp stamp_at(int64_t capture_mono_ns) {
  RtpFrameStamp s;
  s.capture_unix_ns = capture_mono_ns + kHostOffset;
  return s;
}

TEST(RtpFrameStamper, APlainSendersFrameTakesItsEarliestPacketsArrivalRoundedToTheMicrosecond) {
  RtpFrameStamper st(measured(), &host_offset);
  st.note_arrival(100, 5 * kMs + 999);  // 5.000999 ms: 5000 us
  st.note_arrival(101, 4 * kMs);        // the second packet came first (reordered)
  st.add_packet(7, 100, nullptr, 6 * kMs);
  st.add_packet(7, 101, nullptr, 8 * kMs);
  st.add_decoded(7, 9 * kMs);
  const RtpStampedFrame f = st.frame(7, 10 * kMs);
  EXPECT_FALSE(f.stamped);
  EXPECT_EQ(f.arrival_ns, 4 * kMs);
  EXPECT_EQ(f.capture_ns, 4 * kMs);
  EXPECT_EQ(f.stages.received_ns, 8 * kMs);  // its last packet through the jitter buffer
  EXPECT_EQ(f.stages.decoded_ns, 9 * kMs);
  EXPECT_EQ(f.stages.capture_mono_ns, 0);
  EXPECT_FALSE(f.stages.has_revision);
  EXPECT_FALSE(f.capture_after_arrival);
  EXPECT_EQ(st.capture_of(7), 0);
}

TEST(RtpFrameStamper, ASenderStampIsMappedThroughTheSynchronizedClockWithItsStages) {
  RtpFrameStamper st(synchronized(3 * kMs), &host_offset);
  const ClockMapping m = st.clock_mapping(0);
  EXPECT_EQ(m.kind, ClockMapping::Kind::kSynchronized);
  EXPECT_EQ(m.offset_ns, -kHostOffset);
  EXPECT_EQ(m.uncertainty_ns, 3 * kMs);

  RtpFrameStamp s = stamp_at(2 * kMs);
  s.stages = SenderStagesStamp{1500, 2500, 0, 0};
  s.camera = CameraStateStamp{1, 9};
  st.note_arrival(1, 6 * kMs);
  st.add_packet(3, 1, &s, 7 * kMs);
  s.stages->sent_us = 3000;  // the frame's last packet left later: its sent time
  st.add_packet(3, 2, &s, 8 * kMs);
  s.stages->sent_us = 1000;  // an earlier packet through late: sent stays the latest
  st.add_packet(3, 3, &s, 8 * kMs);
  const RtpStampedFrame f = st.frame(3, 10 * kMs);
  EXPECT_TRUE(f.stamped);
  EXPECT_EQ(f.capture_ns, 2 * kMs);
  EXPECT_EQ(f.arrival_ns, 6 * kMs);
  EXPECT_EQ(f.stages.encoded_ns, 2 * kMs + 1500'000);
  EXPECT_EQ(f.stages.sent_ns, 2 * kMs + 3000'000);
  EXPECT_EQ(f.stages.uncertainty_ns, 3 * kMs);
  EXPECT_TRUE(f.stages.has_revision);
  EXPECT_EQ(f.stages.revision, 9u);
  EXPECT_FALSE(f.capture_after_arrival);
  EXPECT_EQ(st.capture_of(3), 2 * kMs);  // a key frame's capture time
}

TEST(RtpFrameStamper, AMeasuredClockMapsThroughTheSenderReportAndHalfTheRoundTrip) {
  RtpFrameStamper st(measured(), &host_offset);
  EXPECT_EQ(st.clock_mapping(0).kind, ClockMapping::Kind::kUnmeasured);
  EXPECT_EQ(st.clock_mapping(0).offset_ns, -kHostOffset);  // until measured: this host's own
  // A sender clock 7 s ahead of this host's realtime; its report arrives 50 ms (mono) here.
  const int64_t sender_ahead = 7'000 * kMs;
  const int64_t arrival = 50 * kMs, sent = arrival - 1 * kMs + kHostOffset + sender_ahead;
  st.add_sender_report(sent, arrival);
  EXPECT_EQ(st.clock_mapping(arrival).kind, ClockMapping::Kind::kUnmeasured);
  RtpFrameStamp rt;
  rt.capture_unix_ns = sent;
  rt.stages = SenderStagesStamp{0, 0, 1, 2000};  // round trip #1: 2 ms
  st.add_packet(std::nullopt, 0, &rt, arrival);  // no frame: feeds the clock only
  ClockMapping m = st.clock_mapping(arrival);
  EXPECT_EQ(m.kind, ClockMapping::Kind::kMeasured);
  // arrival - sent = offset + the one-way delay, taken as half the round trip (1 ms).
  EXPECT_EQ(m.offset_ns, -kHostOffset - sender_ahead);
  EXPECT_EQ(m.uncertainty_ns, 1 * kMs);
  EXPECT_EQ(m.round_trip_ns, 2 * kMs);
  EXPECT_EQ(m.samples, 2u);
  rt.stages->round_trip_us = 500;  // the same round trip's count again: not a new sample
  st.add_packet(std::nullopt, 0, &rt, arrival);
  EXPECT_EQ(st.clock_mapping(arrival).samples, 2u);
  EXPECT_EQ(st.clock_mapping(arrival).round_trip_ns, 2 * kMs);

  // A frame captured 10 ms after the report was sent: 59 ms here.
  RtpFrameStamp s;
  s.capture_unix_ns = sent + 10 * kMs;
  st.note_arrival(40, 62 * kMs);
  st.add_packet(11, 40, &s, 63 * kMs);
  const RtpStampedFrame f = st.frame(11, 70 * kMs);
  EXPECT_TRUE(f.stamped);
  EXPECT_EQ(f.capture_ns, 59 * kMs);
  EXPECT_EQ(f.stages.uncertainty_ns, 1 * kMs);
  EXPECT_EQ(f.stages.encoded_ns, 0);  // no sender-stages element on this one
}

TEST(RtpFrameStamper, ACaptureAfterItsArrivalIsReplacedByTheArrival) {
  RtpFrameStamper st(synchronized(0), &host_offset);
  const RtpFrameStamp s = stamp_at(12 * kMs);
  st.note_arrival(1, 9 * kMs);
  st.add_packet(5, 1, &s, 10 * kMs);
  const RtpStampedFrame f = st.frame(5, 11 * kMs);
  EXPECT_TRUE(f.stamped);
  EXPECT_TRUE(f.capture_after_arrival);
  EXPECT_EQ(f.capture_ns, 9 * kMs);
  EXPECT_EQ(f.stages.capture_mono_ns, 12 * kMs);  // what the mapping said, for the record
}

TEST(RtpFrameStamper, ADelayedSenderReportNeverPutsAMeasuredCaptureAfterItsArrival) {
  RtpFrameStamper st(measured(), &host_offset);
  // The sender's clock is this host's; its report took 40 ms, its round trip says 2 ms.
  st.add_sender_report(1'000 * kMs + kHostOffset, 1'040 * kMs);
  RtpFrameStamp rt = stamp_at(1'000 * kMs);
  rt.stages = SenderStagesStamp{0, 0, 1, 2000};
  st.add_packet(std::nullopt, 0, &rt, 1'040 * kMs);
  ASSERT_EQ(st.clock_mapping(1'040 * kMs).offset_ns, -kHostOffset + 39 * kMs);
  // Frames every 33 ms, each arriving 6 ms after its capture: each admitted, none after its
  // arrival, each within its uncertainty of the truth.
  for (uint16_t i = 0; i < 10; ++i) {
    const int64_t capture = 1'100 * kMs + i * 33 * kMs;
    const RtpFrameStamp s = stamp_at(capture);
    st.note_arrival(i, capture + 6 * kMs);
    st.add_packet(uint64_t(i), i, &s, capture + 7 * kMs);
    const RtpStampedFrame f = st.frame(uint64_t(i), capture + 8 * kMs);
    EXPECT_FALSE(f.capture_after_arrival) << "frame " << i;
    EXPECT_LE(f.capture_ns, f.arrival_ns) << "frame " << i;
    EXPECT_LE(std::llabs(f.capture_ns - capture), f.stages.uncertainty_ns) << "frame " << i;
    EXPECT_TRUE(st.admit(f)) << "frame " << i;
  }
}

TEST(RtpFrameStamper, WithoutAnArrivalStampTheLastPacketsTimeThenTheFramesOwnIsTheArrival) {
  RtpFrameStamper st(measured(), &host_offset);
  st.add_packet(8, 30, nullptr, 3 * kMs);  // retransmissions only: udpsrc's stamps unknown
  st.add_packet(8, 31, nullptr, 4 * kMs);
  EXPECT_EQ(st.frame(8, 5 * kMs).arrival_ns, 4 * kMs);
  EXPECT_EQ(st.frame(8, 3 * kMs).arrival_ns, 3 * kMs);  // never after the frame's own time
  EXPECT_EQ(st.frame(std::nullopt, 6 * kMs).arrival_ns, 6 * kMs);  // no PTS
  EXPECT_EQ(st.frame(1234, 6 * kMs).arrival_ns, 6 * kMs);          // no slot
  EXPECT_EQ(st.frame(1234, 6 * kMs).capture_ns, 6 * kMs);
}

TEST(RtpFrameStamper, ArrivalsAreForgottenWhenOverwrittenOldOrInTheFuture) {
  RtpFrameStamper st(measured(), &host_offset);
  const int64_t s = 1'000 * kMs;
  st.note_arrival(5, s);
  EXPECT_EQ(st.arrival_of(5, s + 500 * kMs), s);
  EXPECT_EQ(st.arrival_of(5, s + RtpFrameStamper::kArrivalMaxAgeNs - 1), s);
  EXPECT_EQ(st.arrival_of(5, s + RtpFrameStamper::kArrivalMaxAgeNs), 0);  // an older round
  EXPECT_EQ(st.arrival_of(5, s - 1), 0);                                  // not yet: refused
  EXPECT_EQ(st.arrival_of(6, s), 0);                                      // never noted
  st.note_arrival(5 + RtpFrameStamper::kArrivals, s + 1 * kMs);           // the same entry
  EXPECT_EQ(st.arrival_of(5, s + 2 * kMs), 0);
  EXPECT_EQ(st.arrival_of(5 + RtpFrameStamper::kArrivals, s + 2 * kMs), s + 1 * kMs);
}

TEST(RtpFrameStamper, OnlyTheNewestSlotsAreKeptAndADecodedFrameWithoutOneGetsItsOwn) {
  RtpFrameStamper st(synchronized(0), &host_offset);
  for (uint64_t pts = 0; pts <= RtpFrameStamper::kSlots; ++pts) {
    const RtpFrameStamp s = stamp_at(int64_t(pts + 1) * kMs);
    st.add_packet(pts, uint16_t(pts), &s, 100 * kMs);
  }
  EXPECT_EQ(st.capture_of(0), 0);  // the oldest frame's slot went to the newest
  EXPECT_EQ(st.frame(0, 200 * kMs).stages.received_ns, 0);
  EXPECT_EQ(st.capture_of(1), 2 * kMs);
  EXPECT_EQ(st.capture_of(RtpFrameStamper::kSlots), int64_t(RtpFrameStamper::kSlots + 1) * kMs);
  st.add_decoded(0, 150 * kMs);  // its decoded frame: a slot for the decode time only
  const RtpStampedFrame f = st.frame(0, 200 * kMs);
  EXPECT_EQ(f.stages.decoded_ns, 150 * kMs);
  EXPECT_FALSE(f.stamped);
  EXPECT_EQ(f.arrival_ns, 200 * kMs);
  EXPECT_EQ(st.capture_of(1), 0);  // which took the next oldest's
}

TEST(RtpFrameStamper, OnlyAFrameNewerThanTheLastAdmittedOneIsAdmitted) {
  RtpFrameStamper st(measured(), &host_offset);
  auto at = [](int64_t capture_ns) {
    RtpStampedFrame f;
    f.capture_ns = capture_ns;
    return f;
  };
  EXPECT_TRUE(st.admit(at(5 * kMs)));
  EXPECT_FALSE(st.admit(at(5 * kMs)));  // the same time again: not new
  EXPECT_FALSE(st.admit(at(4 * kMs)));  // late
  EXPECT_TRUE(st.admit(at(6 * kMs)));
  EXPECT_FALSE(st.admit(at(5 * kMs + 999'999)));  // the last admitted is 6 ms now
}

}  // namespace
}  // namespace hd::drivers
