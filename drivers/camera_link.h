#pragma once
// The network side of a camera, as the station sees it: what the link received, and the view
// need it passes to the sender. A network camera implements it beside CameraSource; a camera on
// this host has none, so the station holds one only where the assembler found one (no casts).

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace hd::drivers {

/// What a link received and sent since start(), in the terms the station's summary reports
/// (drivers/rtp/rtp_camera.h's counters for RTP). Clock figures: capture_mono = sender_unix +
/// clock_offset_ns, within ±clock_uncertainty_ns (-1 unknown).
struct LinkReport {
  std::string security;  ///< "SRTP AES-128-GCM (key file F)" or "none"
  uint64_t packets = 0, bytes = 0, malformed = 0, srtp_rejected = 0;
  /// The malformed packets by reason (RtpPacketError's words), reasons with none left out.
  std::vector<std::pair<std::string, uint64_t>> malformed_by_reason;
  uint64_t frames_stamped = 0;    ///< with the sender's capture time
  uint64_t frames_unstamped = 0;  ///< with their arrival time instead
  uint64_t not_newer = 0;         ///< decoded frames not newer than the last shown: dropped
  uint64_t bus_errors = 0;
  uint64_t pli_sent = 0, nack_sent = 0, rtx_received = 0;
  /// Packets the jitter buffer gave up on: rebuilt from FEC, or lost (the frames up to the next
  /// key frame with them).
  uint64_t fec_recovered = 0, lost = 0;
  uint64_t view_feedback_sent = 0;  ///< view-need messages sent to the sender
  uint64_t calibration_errors = 0;  ///< calibration elements refused
  std::string last_error;           ///< the newest error's text ("" none)
  std::string clock_mapping;        ///< how the sender's clock is mapped ("measured", ...)
  int64_t clock_offset_ns = 0, clock_uncertainty_ns = -1, clock_round_trip_ns = -1;
  uint64_t clock_samples = 0, sender_reports = 0;
  /// The sender's CLOCK_REALTIME minus this station's, and the whole mapping in words.
  int64_t clock_sites_offset_ns = 0;
  std::string clock_text;
  uint64_t capture_after_arrival = 0;  ///< mapped capture times after the arrival: replaced
  /// The receive path's losses before a frame could be shown (drivers/rtp/rtp_camera_stats.h):
  /// the socket's kernel buffer asked / given / the system's limit (bytes; -1 unknown), and in
  /// words with what to do when it got less; datagrams the kernel dropped (-1 unknown); packets
  /// the jitter buffer dropped; frames decoded and frames through the conversion.
  int64_t receive_buffer_asked = 0, receive_buffer_bytes = -1, rmem_max_bytes = -1;
  int64_t rtcp_buffer_asked = 0, rtcp_buffer_bytes = -1;
  std::string receive_buffer;
  int64_t kernel_drops = -1;
  uint64_t jitter_too_late = 0, jitter_over_latency = 0;
  uint64_t frames_decoded = 0, frames_converted = 0;
};

class CameraLink {
 public:
  virtual ~CameraLink() = default;
  /// Bandwidth follows the view: whether the station needs this camera at full rate now.
  /// Lock-free: the frame loop calls it between frames.
  virtual void set_view_needed(bool needed) = 0;
  /// What set_view_needed said last (true before the first call: full rate).
  virtual bool view_needed() const = 0;
  /// The counters now (any thread but the render thread: may take a lock).
  virtual LinkReport link_report() const = 0;
};

}  // namespace hd::drivers
