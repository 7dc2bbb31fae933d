#pragma once
// One camera's outgoing RTP H.264 stream at the remote site: frames in, stamped packets out.

#include <gst/gst.h>
#include <gst/rtp/rtp.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "drivers/frame.h"
#include "drivers/rtp/rtp_calibration.h"
#include "drivers/rtp/view_feedback.h"
#include "remote/sender/encoder_input.h"
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
  /// Bandwidth follows the view: valid station messages, malformed ones (by reason, counted and
  /// ignored), frames not sent while not needed, key frames forced on becoming needed again.
  uint64_t view_feedback_received = 0;
  std::array<uint64_t, static_cast<std::size_t>(drivers::ViewFeedbackError::kCount)>
      view_feedback_malformed{};
  uint64_t frames_skipped_not_needed = 0;
  uint64_t key_frames_forced = 0;
  bool needed = true;           ///< as of the last push()
  uint64_t sender_reports = 0;  ///< RTCP sender reports sent
  uint64_t round_trips = 0;     ///< round trips measured from the station's receiver reports
  int64_t round_trip_ns = -1;   ///< the newest (-1 none yet)
  uint64_t packets_with_calibration = 0;  ///< last packets of frames that got the calibration
};

/// Builds send_pipeline_description(), adds GStreamer's rtphdrextntp64 (id 1, every packet) to
/// the payloader and the camera-state element (id 2, drivers/rtp/rtp_frame_stamp.h) to every
/// packet, and, when the config has p_c, the calibration element (id 3,
/// drivers/rtp/rtp_calibration.h) to the last packet of every frame (the marker packet, which
/// then uses RFC 8285's two-byte form for all its elements), then takes RGBA frames with push().
/// Each frame's capture time (its host_timestamp_ns, CLOCK_MONOTONIC) is sent as CLOCK_REALTIME in
/// NTP format (RFC 6051 ntp-64), the clock of its RTCP sender reports, from which the station
/// measures the offset between the two; the frame's PTS on the pipeline (also CLOCK_MONOTONIC) is
/// its capture time, so the encoder sees the real frame spacing. Every packet also carries the
/// sender-stages element (id 4): encode and send times after capture, and the newest round trip
/// measured from the station's receiver reports.
class RtpSender {
 public:
  explicit RtpSender(RtpSendConfig config);
  ~RtpSender();
  RtpSender(const RtpSender&) = delete;
  RtpSender& operator=(const RtpSender&) = delete;

  void start();  ///< throws std::runtime_error naming the destination
  void stop();
  /// Converts `f` (RGBA8 at the configured size) into the encoder's input format, in a reused
  /// buffer, and queues it; never blocks (a full queue drops its oldest frame). False when
  /// refused.
  bool push(const drivers::Frame& f);

  /// A new p_c / P_c (a recalibration, or a camera that moved): the revision goes up by one and
  /// the next frames carry it. Any thread. False when it cannot be sent (not a valid pinhole or
  /// pose, a distortion count other than 0/4/5/8).
  bool set_calibration(const core::Pinhole& p_c, const core::Pose& T_world_cam);
  uint32_t calibration_revision() const { return revision_.load(std::memory_order_acquire); }

  RtpSenderStats stats() const;
  const RtpSendConfig& config() const { return config_; }
  std::string description() const;
  /// The local UDP port RTCP leaves from and the station's feedback (RTCP, view feedback) comes
  /// to; 0 before start().
  uint16_t rtcp_port() const { return rtcp_port_; }

 private:
  GstPadProbeReturn on_encoded(GstPadProbeInfo* info);
  GstPadProbeReturn on_packets(GstPadProbeInfo* info);
  bool stamp_packet(GstBuffer* buffer);
  bool add_calibration(GstRTPBuffer& rtp);
  bool set_calibration(const core::Pinhole& p_c, const core::Pose& T_world_cam, bool next_revision);
  GstPadProbeReturn on_view_feedback(GstBuffer* buffer);
  bool needed_now(int64_t now_ns) const;
  GstPadProbeReturn on_rtcp_out(GstPadProbeInfo* info);
  GstPadProbeReturn on_rtcp_in(GstBuffer* buffer);
  int64_t sender_realtime_ns() const;  // the host's CLOCK_REALTIME + test_clock_shift_ns

  RtpSendConfig config_;
  GstElement* pipeline_ = nullptr;
  GstElement* appsrc_ = nullptr;
  GstElement* rtxsend_ = nullptr;  // inside rtpbin's aux sender (retransmission only)
  EncoderInput input_;             // push()'s thread
  GstCaps* ntp_caps_ = nullptr;    // timestamp/x-ntp: the capture time meta's reference
  GstClockTime base_time_ = 0;
  bool playing_ = false;
  std::atomic<uint64_t> pushed_{0}, refused_{0}, packets_stamped_{0}, frames_stamped_{0},
      packets_calibrated_{0};
  std::atomic<uint64_t> frames_encoded_{0}, key_frames_{0}, last_key_frame_index_{0};
  uint16_t rtcp_port_ = 0;
  // View feedback: written by the RTCP source's streaming thread, read by push().
  std::atomic<bool> station_needs_{true};
  std::atomic<int64_t> last_feedback_ns_{0};  // 0: none yet (full rate)
  std::atomic<int> last_sequence_{-1};
  // With an SRTP key, only view feedback tagged with it is taken (drivers/rtp/view_feedback.h).
  std::optional<drivers::ViewFeedbackKey> view_key_;
  std::atomic<uint64_t> feedback_received_{0};
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(drivers::ViewFeedbackError::kCount)>
      feedback_malformed_{};
  // push()'s thread only.
  bool was_needed_ = true;
  uint64_t push_index_ = 0;
  std::atomic<uint64_t> skipped_{0}, forced_{0};
  std::atomic<bool> needed_reported_{true};
  std::atomic<uint64_t> sender_reports_{0}, round_trips_{0};
  std::atomic<int64_t> round_trip_ns_{-1};
  // Streaming thread of the payloader: when the frame now being packetised reached it.
  GstClockTime encoded_pts_ = GST_CLOCK_TIME_NONE;
  int64_t encoded_mono_ns_ = 0;
  int64_t encoded_capture_ns_ = 0;  // its capture time (CLOCK_MONOTONIC), 0 unknown
  std::atomic<uint32_t> revision_{0};
  // The encoded calibration element (set_calibration's thread -> the streaming thread).
  std::mutex calibration_mutex_;
  std::array<uint8_t, drivers::kCalibrationMaxSize> calibration_element_{};
  std::size_t calibration_size_ = 0;
};

}  // namespace hd::remote
