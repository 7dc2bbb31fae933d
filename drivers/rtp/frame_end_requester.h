#pragma once
// FrameEndWatch wired to GStreamer: its timer on the system clock (CLOCK_MONOTONIC), its request
// sent as the jitter buffer's own retransmission request (the "GstRTPRetransmissionRequest"
// upstream event, which rtprtxreceive notes and rtpsession sends as an RTCP NACK).
//
// The jitter buffer takes a retransmission only for a packet it is waiting for, and it does not
// wait for a packet after the newest it has (rtx-next-seqnum is off, rtp_camera_wiring.cpp): the
// repair of a packet asked for here is passed to it as the packet itself (its RETRANSMISSION flag
// cleared at the jitter buffer's input, take_repair()).
//
// Shared: the clock's thread holds it while a timer is pending, so the camera's shutdown() only
// makes it inert; packets come from the streaming thread; a mutex guards it.
#include <gst/gst.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>

#include "drivers/rtp/frame_end_watch.h"

namespace hd::drivers {

class FrameEndRequester : public std::enable_shared_from_this<FrameEndRequester> {
 public:
  static std::shared_ptr<FrameEndRequester> create(FrameEndWatch::Settings s);
  ~FrameEndRequester();

  /// The stream's jitter buffer (rtpbin's new-jitterbuffer; ref taken), and a fresh watch.
  void set_jitter_buffer(GstElement* jitter_buffer);
  /// A media packet (or the repair of one, with its original sequence number) into rtpbin;
  /// `ssrc` the stream's (0 for a repair: it comes on the RTX SSRC).
  void on_packet(uint32_t ssrc, uint16_t sequence, bool marker, int64_t arrival_ns);
  /// At the jitter buffer's input: true when `sequence` is the repair of a packet asked for here
  /// (the caller clears its RETRANSMISSION flag).
  bool take_repair(uint16_t sequence);
  /// What the request tells rtpsession: how long the repair is of use (the jitter buffer's
  /// latency) and the round trip, ms.
  void set_deadline(int latency_ms, int round_trip_ms);
  /// The wait before a missing frame end is asked for (JitterBudget::request_wait_ns()).
  void set_wait(int64_t wait_ns);
  /// No more timers or requests; the jitter buffer's ref released.
  void shutdown();
  uint64_t requests() const;

 private:
  explicit FrameEndRequester(FrameEndWatch::Settings s) : watch_(s) {}
  void arm();  // m_ held: one pending timer, at the watch's due time
  void on_timer();

  mutable std::mutex m_;
  FrameEndWatch watch_;
  FrameEndWatch::Settings settings_{};
  GstElement* jitter_buffer_ = nullptr;
  GstClock* clock_ = nullptr;
  GstClockID timer_ = nullptr;
  int64_t timer_due_ns_ = 0;
  uint32_t ssrc_ = 0;
  int deadline_ms_ = 20, round_trip_ms_ = 1;
  bool live_ = true;
  std::array<uint16_t, 32> asked_{};  // the newest requests, for take_repair
  std::size_t asked_next_ = 0, asked_count_ = 0;
  uint64_t requests_ = 0;
};

}  // namespace hd::drivers
