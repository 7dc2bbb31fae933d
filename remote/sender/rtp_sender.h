#pragma once
// One camera's outgoing RTP H.264 stream at the remote site: frames in, stamped packets out.

#include <gst/gst.h>

#include <atomic>
#include <cstdint>
#include <string>

#include "drivers/frame.h"
#include "remote/sender/rtp_send_config.h"

namespace hd::remote {

struct RtpSenderStats {
  uint64_t frames_pushed = 0;
  uint64_t frames_refused = 0;        ///< wrong size, or captured before the pipeline started
  uint64_t packets_stamped = 0;       ///< packets that got the camera-state element
  uint64_t frames_stamped = 0;        ///< encoded frames that got their capture time (ntp-64)
  uint64_t frames_encoded = 0;        ///< frames out of the encoder (index of the next one)
  uint64_t key_frames = 0;            ///< of them IDRs (not delta units): periodic and requested
  uint64_t last_key_frame_index = 0;  ///< the newest IDR's index among frames_encoded
  /// RTX: NACKed packets asked for (rtprtxsend's retransmission events) / sent again.
  uint64_t rtx_requests = 0;
  uint64_t rtx_packets_sent = 0;
};

/// Builds send_pipeline_description(), adds GStreamer's rtphdrextntp64 (id 1, every packet) to
/// the payloader and the camera-state element (id 2, drivers/rtp/rtp_frame_stamp.h) to every
/// packet, then takes RGBA frames with push(). Each frame's capture time (its host_timestamp_ns,
/// CLOCK_MONOTONIC) is sent as CLOCK_REALTIME in NTP format (RFC 6051 ntp-64), so a station on
/// another host with synchronised clocks can map it; the frame's PTS on the pipeline (also
/// CLOCK_MONOTONIC) is its capture time, so the encoder sees the real frame spacing.
class RtpSender {
 public:
  explicit RtpSender(RtpSendConfig config);
  ~RtpSender();
  RtpSender(const RtpSender&) = delete;
  RtpSender& operator=(const RtpSender&) = delete;

  void start();  ///< throws std::runtime_error naming the destination
  void stop();
  /// Copies `f` (RGBA8 at the configured size) into a GStreamer buffer and queues it; never
  /// blocks (a full queue drops its oldest frame). False when refused.
  bool push(const drivers::Frame& f);

  RtpSenderStats stats() const;
  const RtpSendConfig& config() const { return config_; }
  std::string description() const;

 private:
  GstPadProbeReturn on_encoded(GstPadProbeInfo* info);
  GstPadProbeReturn on_packets(GstPadProbeInfo* info);
  bool stamp_packet(GstBuffer* buffer);

  RtpSendConfig config_;
  GstElement* pipeline_ = nullptr;
  GstElement* appsrc_ = nullptr;
  GstElement* rtxsend_ = nullptr;  // inside rtpbin's aux sender (retransmission only)
  GstClockTime base_time_ = 0;
  bool playing_ = false;
  std::atomic<uint64_t> pushed_{0}, refused_{0}, packets_stamped_{0}, frames_stamped_{0};
  std::atomic<uint64_t> frames_encoded_{0}, key_frames_{0}, last_key_frame_index_{0};
};

}  // namespace hd::remote
