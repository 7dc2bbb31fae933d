#pragma once
// The station's network camera: one RTP H.264 stream (from hybrid-remote or any standard sender)
// received through GStreamer, as a CameraSource.

#include <gst/gst.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "drivers/camera_link.h"
#include "drivers/camera_source.h"
#include "drivers/format_watch.h"
#include "drivers/rtp/clock_offset_estimator.h"
#include "drivers/rtp/rtp_calibration.h"
#include "drivers/rtp/rtp_frame_stamp.h"
#include "drivers/rtp/rtp_packet.h"
#include "drivers/rtp/rtp_receive_config.h"
#include "drivers/rtp/rtp_stream_guard.h"
#include "drivers/rtp/view_feedback.h"
#include "drivers/spsc_ring.h"

namespace hd::drivers {

/// When one frame crossed each stage of the link, for its latency (CLOCK_MONOTONIC ns; 0 = not
/// known: a plain sender stamps no encode or send time).
struct RtpFrameTiming {
  uint64_t sequence = 0;
  int64_t capture_ns = 0;  ///< the sender's capture time, mapped (or the arrival if unstamped)
  int64_t encoded_ns = 0;  ///< the sender's encoder output (capture + its sender-stages offset)
  int64_t sent_ns = 0;     ///< its last packet left the sender's payloader (likewise)
  /// udpsrc's arrival stamp of its earliest packet (read when udpsrc took it off the socket,
  /// before rtpbin), or received_ns when none is known (a frame of retransmissions only).
  int64_t arrival_ns = 0;
  /// its last packet left the jitter buffer (at the depayloader): received whole, as sent_ns is
  /// its last packet leaving the sender
  int64_t received_ns = 0;
  int64_t decoded_ns = 0;    ///< avdec_h264 output it
  int64_t published_ns = 0;  ///< converted to RGBA and in the mailbox
  /// capture_ns (and so encoded_ns, sent_ns) is true to within this (-1 unknown); 0 unstamped.
  int64_t clock_uncertainty_ns = -1;
  bool stamped = false;
};

/// Counters since start(); read from any thread.
struct RtpCameraStats {
  uint64_t packets = 0;  ///< UDP datagrams that reached the RTP port
  uint64_t bytes = 0;    ///< their UDP payload bytes
  /// Times the RTCP feedback destination was set (the first sender's RTCP address, then each
  /// new one).
  uint64_t feedback_targets = 0;
  /// Packets refused by parse_rtp_packet or check_h264_payload (dropped before rtpbin or, with a
  /// key, right after srtpdec), by reason.
  std::array<uint64_t, static_cast<std::size_t>(RtpPacketError::kCount)> malformed{};
  uint64_t malformed_total = 0;
  uint64_t accepted = 0;  ///< passed on to GStreamer: packets = accepted + malformed_total
  /// Times the stream's sequence numbering was taken anew because two consecutive packets
  /// continued a jump (RtpStreamGuard: a sender that renumbered); the jump's first packet is
  /// counted in malformed[kSequenceJump].
  uint64_t sequence_resyncs = 0;
  uint64_t frames_published = 0;
  uint64_t wrong_format = 0;  ///< decoded frames of another size than negotiated (not published)
  uint64_t bus_errors = 0;    ///< GStreamer errors (each restarts the pipeline)
  /// Frames with the sender's capture time (hybrid-remote) / with their arrival time instead.
  uint64_t stamped_frames = 0;
  uint64_t unstamped_frames = 0;
  /// Stamped frames whose mapped capture time lay after their arrival (the two clocks disagree):
  /// stamped with the arrival instead.
  uint64_t capture_after_arrival = 0;
  /// Decoded frames not newer than the last published one (a late or repeated frame): never
  /// published, so old video is never presented as new.
  uint64_t not_newer = 0;
  /// Packets with header extensions whose stamp was refused, by reason (StampError).
  std::array<uint64_t, static_cast<std::size_t>(StampError::kCount)> stamp_errors{};
  /// With a key: packets srtpdec authenticated and decrypted / that failed (a wrong key, or a
  /// sender without encryption): never decoded, never shown.
  uint64_t srtp_decrypted = 0;
  uint64_t srtp_rejected = 0;
  /// Calibration elements (id 3) refused, by reason (CalibrationError); the element is ignored.
  std::array<uint64_t, static_cast<std::size_t>(CalibrationError::kCount)> calibration_errors{};
  uint64_t calibration_errors_total = 0;
  uint64_t calibrations_received = 0;    ///< calibration elements accepted
  uint64_t frames_with_calibration = 0;  ///< published frames that carry the stream's calibration
  /// Decoded frames whose size is not their calibration's image size: never published.
  uint64_t calibration_size_mismatch = 0;
  /// The newest accepted calibration (none: the sender sends none, or none arrived yet).
  std::optional<StreamCalibration> calibration;
  int last_camera_index = -1;  ///< from the camera-state element; -1 none seen
  int64_t last_calibration_revision = -1;
  uint64_t restarts = 0;
  /// Decoded key frames (IDR access units out of the depayloader), and the newest one's capture
  /// time (0: none or unstamped).
  uint64_t key_frames = 0;
  int64_t last_key_frame_capture_ns = 0;
  std::string last_error;       ///< the newest bus error's text ("" none)
  ClockMapping clock;           ///< the sender-clock mapping in use now
  uint64_t sender_reports = 0;  ///< RTCP sender reports received (clock samples)
};

/// Receives `rtp://HOST:PORT`: the pipeline of receive_pipeline_description() (udpsrc → rtpbin
/// with a small jitter buffer and NACK/RTX → rtph264depay → avdec_h264 → RGBA → appsink), whose
/// appsink callback copies each decoded frame into the pre-sized mailbox (no allocation once the
/// three slots are sized; the render thread only fetches).
///
/// Size: negotiate() takes the calibrated size as the expected one (the stream cannot be asked
/// for a size, so the answer is "unknown until the first frame"); a decoded frame of another size
/// is never published: the state becomes kFormatMismatch with a FormatEvent. open() without a
/// size learns it from the first frame.
///
/// Time: a frame stamped by hybrid-remote (rtp_frame_stamp.h: ntp-64 on every packet) carries
/// its capture time on the sender's CLOCK_REALTIME; it is mapped onto CLOCK_MONOTONIC through
/// the offset measured from the sender's RTCP sender reports and its round trip
/// (ClockOffsetEstimator; until the first of both, this host's realtime - monotonic offset,
/// exact on one machine only), or with `Clock::kSynchronized` through this host's realtime -
/// monotonic offset with the sites' stated error; device_time_trusted is then true. A
/// mapped time after the frame's arrival is impossible and replaced by the arrival (counted). A
/// plain sender says nothing about when it captured a frame, so its host time is its arrival:
/// the jitter buffer's output time of its packets (udpsrc's arrival stamps, with the jitter
/// buffer's skew estimate) on the pipeline clock, which is CLOCK_MONOTONIC; not trusted.
///
/// Liveness: no frame for stall_timeout_ns makes the state kStalled; a GStreamer error makes it
/// kDisconnected, is counted with its text, and the pipeline is rebuilt after 0.5 s.
///
/// Calibration: a sender that streams p_c and P_c (hybrid-remote: the calibration element on the
/// last packet of every frame, rtp_calibration.h) has each frame published with the calibration
/// of its camera-state revision in Frame::calibration; a refused element is counted by reason and
/// ignored, and a frame whose size is not its calibration's is not published (counted). Frames of
/// a sender that sends none carry none (the station's calibration file applies).
///
/// Bad input: every UDP datagram on the RTP port is checked with parse_rtp_packet and its H.264
/// payload with check_h264_payload (after srtpdec with a key) before the depayloader sees it; a
/// malformed one is dropped and counted by reason.
class RtpCamera final : public CameraSource, public CameraLink {
 public:
  explicit RtpCamera(RtpReceiveConfig config);
  ~RtpCamera() override;
  RtpCamera(const RtpCamera&) = delete;
  RtpCamera& operator=(const RtpCamera&) = delete;

  std::string id() const override { return to_uri(config_.listen); }
  void open() override;  ///< builds the pipeline (throws DeviceError naming the address)
  FormatNegotiation negotiate(const CameraFormatRequest& wanted) override;
  CameraFormat format() const override { return format_; }
  bool pop_format_event(FormatEvent& out) override { return format_watch_.pop(out); }
  void start() override;  ///< starts listening (throws DeviceError when the port is taken)
  void stop() override;
  SourceState state() const override { return state_.load(std::memory_order_acquire); }
  uint64_t dropped_frames() const override;
  Mailbox<Frame>& frames() override { return *mailbox_; }

  RtpCameraStats stats() const;
  /// The sender-clock mapping in use now (any thread; not the render thread: takes a mutex).
  ClockMapping clock_mapping() const;
  /// RTCP feedback this station sent to the sender so far, from rtpbin's session statistics:
  /// picture loss indications (key-frame requests) and NACKs. Not for the render thread.
  struct Feedback {
    uint64_t pli_sent = 0;
    uint64_t nack_sent = 0;
    uint64_t rtcp_received_from_sender = 0;  ///< sender reports seen (have-sr)
    /// Key frames this camera asked for itself when packets came back after a stall (each
    /// becomes an RTCP PLI); the depayloader asks on its own on every detected loss.
    uint64_t key_frame_requests = 0;
    /// RTX (this pipeline's rtprtxreceive): packets the jitter buffer asked to be sent again,
    /// and retransmissions (RFC 4588 packets of the RTX payload type) received.
    uint64_t rtx_requested = 0;
    uint64_t rtx_received = 0;
    uint64_t view_feedback_sent = 0;  ///< HDBW messages sent (set_view_needed)
  };
  Feedback feedback() const;
  /// Asks the sender for a key frame now: an upstream force-key-unit event from the
  /// depayloader, which rtpbin sends as an RTCP PLI. False when the pipeline is not built. Not
  /// for the render thread.
  bool request_key_frame();
  /// Bandwidth follows the view: tells the sender whether the station needs this camera at full
  /// rate (an RTCP APP "HDBW" message, drivers/rtp/view_feedback.h, to where the sender's RTCP
  /// comes from; sent now when it changes and every 0.5 s from the bus thread). Never called:
  /// nothing is sent and the sender stays at full rate. Lock-free (one atomic store): the frame
  /// loop may call it between frames.
  void set_view_needed(bool needed) override;
  /// What set_view_needed said last (true before: full rate).
  bool view_needed() const override { return view_need_.load(std::memory_order_relaxed) != 0; }
  /// stats() and feedback() as the station's summary reports them (rtp_link_report.cpp).
  LinkReport link_report() const override;
  /// Fault injection (config.netsim() only): netsim's drop probability while running; 1 cuts the
  /// link. False when there is no netsim in the path.
  bool set_netsim_drop_probability(double p);
  /// Oldest unread frame timing (bounded queue; overflow is counted by the ring and dropped).
  bool pop_timing(RtpFrameTiming& out) { return timings_.pop(out); }
  const RtpReceiveConfig& config() const { return config_; }
  /// The pipeline as built (for the start report and docs).
  std::string pipeline_description() const;

 private:
  void build();
  void teardown();
  void bus_loop();
  void on_sample(GstElement* sink);
  RtpPacketError check_payload(const RtpPacketView& view) const;
  GstPadProbeReturn on_rtp_packet(GstBuffer* buffer);
  GstPadProbeReturn on_decrypted(GstBuffer* buffer);
  void on_depay_packet(GstBuffer* buffer);
  void on_rtcp_into_rtpbin(GstBuffer* buffer);
  void on_decoded(GstBuffer* buffer);
  static GstPadProbeReturn depay_probe_cb(GstPad* pad, GstPadProbeInfo* info, gpointer self);
  static GstFlowReturn new_sample_cb(GstElement* sink, gpointer self);
  static GstPadProbeReturn rtp_probe_cb(GstPad* pad, GstPadProbeInfo* info, gpointer self);
  static GstPadProbeReturn rtcp_probe_cb(GstPad*, GstPadProbeInfo* info, gpointer self);

  RtpReceiveConfig config_;
  CameraFormat format_;  // negotiated: expected size, H.264 on the wire
  std::unique_ptr<Mailbox<Frame>> mailbox_;
  GstElement* pipeline_ = nullptr;

  std::thread bus_thread_;
  std::atomic<bool> running_{false};
  std::atomic<SourceState> state_{SourceState::kClosed};
  std::atomic<int64_t> last_frame_ns_{0};

  // Owned by the streaming thread.
  int learned_width_ = 0, learned_height_ = 0;
  uint64_t sequence_ = 0;
  int sized_slots_ = 0;

  std::atomic<uint64_t> packets_{0}, bytes_{0}, feedback_targets_{0};
  // The media SSRC, sequence numbers and RTP times taken (udpsrc's streaming thread, or
  // srtpdec's with a key: one thread either way).
  RtpStreamGuard stream_guard_;
  std::atomic<uint64_t> stream_resyncs_{0};
  // udpsrc's arrival stamp of `buffer` on CLOCK_MONOTONIC (the pipeline clock), or now.
  int64_t arrival_ns(GstBuffer* buffer) const;
  std::string feedback_to_;   // RTCP source thread: where feedback goes now
  void send_view_feedback();  // any thread; takes view_mutex_
  std::mutex view_mutex_;
  std::string view_host_;  // where the sender's RTCP comes from (under view_mutex_)
  int view_port_ = 0;
  std::atomic<int> view_need_{-1};  // -1: never set; written by set_view_needed (lock-free)
  // Bus thread only: what was sent last and when (0: send at the next turn).
  int view_sent_need_ = -1;
  uint16_t view_sequence_ = 0;
  std::optional<ViewFeedbackKey> view_key_;  // from the SRTP key: the feedback is then tagged
  int64_t view_sent_ns_ = 0;                 // under view_mutex_ (a new sender resets it)
  std::atomic<uint64_t> view_sent_{0};
  std::atomic<uint64_t> key_frames_{0};
  std::atomic<int64_t> last_key_capture_ns_{0};
  SpscRing<RtpFrameTiming, 1024> timings_;
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(RtpPacketError::kCount)> malformed_{};
  std::atomic<uint64_t> frames_published_{0};
  // Set when a stalled camera that had shown video asked for a key frame; cleared by the next
  // published frame, so each outage asks once (more come from the depayloader on every loss).
  std::atomic<bool> key_frame_requested_{false};
  std::atomic<uint64_t> key_frame_requests_{0};
  std::atomic<uint64_t> wrong_format_{0};
  std::atomic<uint64_t> bus_errors_{0};
  std::atomic<uint64_t> restarts_{0};
  std::atomic<uint64_t> well_formed_{0}, decrypted_{0};
  std::atomic<uint64_t> stamped_{0}, unstamped_{0}, capture_after_arrival_{0}, not_newer_{0};
  int64_t last_published_capture_ns_ = 0;  // streaming thread
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(StampError::kCount)> stamp_errors_{};
  std::atomic<int> last_camera_index_{-1};
  std::atomic<int64_t> last_revision_{-1};
  // Capture times by buffer PTS, from the depayloader's input (after the jitter buffer) to the
  // decoded frame (the decoder keeps PTS). Fixed size: a few frames in flight at most.
  struct StampSlot {
    uint64_t pts = ~0ull;
    int64_t capture_mono_ns = 0;
    int64_t encoded_ns = 0, sent_ns = 0;  // 0: no sender-stages element
    int64_t received_ns = 0;              // its last packet at the depayloader
    int64_t arrival_ns = 0;               // udpsrc's stamp of its earliest packet (0 unknown)
    int64_t uncertainty_ns = -1;
    int64_t decoded_ns = 0;
    bool has_revision = false;  // the packets' camera-state revision
    uint32_t revision = 0;
  };
  // The newest accepted calibrations (newest first), looked up by a frame's revision.
  std::array<std::optional<StreamCalibration>, 4> calibrations_{};
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(CalibrationError::kCount)>
      calibration_errors_{};
  std::atomic<uint64_t> calibrations_received_{0}, frames_with_calibration_{0},
      calibration_size_mismatch_{0};
  mutable std::mutex stamp_mutex_;
  // The sender-clock estimate: sender reports from the RTCP thread, round trips from the
  // depayloader's.
  mutable std::mutex clock_mutex_;
  ClockOffsetEstimator clock_;
  uint8_t last_round_trip_count_ = 0;  // depayloader thread
  std::atomic<uint64_t> sender_reports_{0};
  std::array<StampSlot, 16> stamps_{};
  // udpsrc's arrival stamp of each media packet passed on, by sequence number, for the
  // depayloader's side (the jitter buffer replaces the buffer's timestamps with its own estimate,
  // which may lie after the frame was decoded): (arrival in us << 16) | sequence, one atomic
  // store (udpsrc's thread) and load (the jitter buffer's). 48 bits of microseconds last 8 years.
  std::array<std::atomic<uint64_t>, 1024> arrivals_{};
  void note_arrival(uint16_t sequence, int64_t arrival_ns);
  int64_t arrival_of(uint16_t sequence, int64_t now_ns) const;  // 0: not known (any more)
  // Finds or makes the slot of `pts` (under stamp_mutex_) and notes a packet's arrival in it.
  StampSlot& stamp_slot(uint64_t pts, int64_t arrival_ns, int64_t now_ns);
  std::size_t stamp_next_ = 0;
  mutable std::mutex error_mutex_;
  std::string last_error_;
  FormatWatch format_watch_;  // streaming thread; the station pops its events
};

}  // namespace hd::drivers
