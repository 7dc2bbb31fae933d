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
#include <utility>

#include "drivers/camera_link.h"
#include "drivers/camera_source.h"
#include "drivers/format_watch.h"
#include "drivers/gobject_ptr.h"
#include "drivers/gst/pipeline_runner.h"
#include "drivers/gst/rgba_converter.h"
#include "drivers/rtp/access_unit_pts.h"
#include "drivers/rtp/clock_offset_estimator.h"
#include "drivers/rtp/frame_end_requester.h"
#include "drivers/rtp/h264_heal_watch.h"
#include "drivers/rtp/jitter_budget.h"
#include "drivers/rtp/rtp_calibration_cache.h"
#include "drivers/rtp/rtp_camera_stats.h"
#include "drivers/rtp/rtp_frame_stamper.h"
#include "drivers/rtp/rtp_packet.h"
#include "drivers/rtp/rtp_receive_config.h"
#include "drivers/rtp/rtp_receive_socket.h"
#include "drivers/rtp/rtp_stream_guard.h"
#include "drivers/rtp/view_feedback_schedule.h"
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

/// Receives `rtp://HOST:PORT`: the pipeline of receive_pipeline_description() (udpsrc → rtpbin
/// with a small jitter buffer and NACK/RTX → queue → rtph264depay → avdec_h264 → RGBA → appsink),
/// whose appsink callback copies each decoded frame into the pre-sized mailbox (no allocation once
/// the three slots are sized; the render thread only fetches).
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
///
/// Losses: the RTP socket's kernel buffer is sized for bursts and a busy machine
/// (RtpReceiveConfig::receive_buffer_bytes; the start report says what the system gave), and what
/// the receive path drops is counted where it happens: the kernel's drops on the socket, the
/// jitter buffer's, the frames between decoder and appsink (stats()).
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
    uint64_t pli_sent = 0;   ///< rtpsession's, and those sent at once (rtp_camera_nack.cpp)
    uint64_t nack_sent = 0;  ///< rtpsession's, and those sent at once (rtp_camera_nack.cpp)
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
  bool view_needed() const override { return view_.needed(); }
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
  // The parts it composes: the pipeline and its bus thread (drivers/gst/pipeline_runner.h), the
  // frame times (rtp_frame_stamper.h), the streamed calibrations (rtp_calibration_cache.h), the
  // view feedback's cadence (view_feedback_schedule.h) and the counters (rtp_camera_stats.h).
  // This class wires them to the pipeline's probes (rtp_camera_wiring.cpp).
  void wire(PipelineRunner& pipeline);  // the runner's wire hook: signals, keys, probes
  void on_bus_error();                  // bus thread
  void on_bus_turn();                   // bus thread: view feedback, stall check
  void send_view_feedback();            // bus thread
  void on_sample(GstElement* sink);
  RtpPacketError check_payload(const RtpPacketView& view) const;
  bool is_fec(int payload_type) const {  // a FEC packet, or its repair
    return config_.fec && (payload_type == config_.fec_payload_type ||
                           payload_type == config_.rtx_fec_payload_type);
  }
  RtpPacketError check_stream(const RtpPacketView& view, GstBuffer* buffer);
  GstPadProbeReturn on_rtp_packet(GstBuffer* buffer);
  GstPadProbeReturn on_decrypted(GstBuffer* buffer);
  void on_depay_packet(GstPad* pad, GstBuffer*& buffer);  // may replace it (its PTS)
  bool on_access_unit(GstPad* pad, GstBuffer*& buffer);   // false: drop it; may replace it
  // Healing after a loss (rtp_camera_heal.cpp): the depayloader's lost events, each access
  // unit's verdict (and a PLI when refresh does not heal), and a decoded frame's verdict.
  void on_packet_lost();
  bool judge_access_unit(GstPad* pad, GstBuffer*& buffer);  // false: drop it; else marked
  void on_rtcp_into_rtpbin(GstBuffer* buffer);
  void on_rtcp_from_sender(GstBuffer* buffer);
  void set_feedback_target(GstBuffer* buffer, bool from_rtcp);
  void on_decoded(GstBuffer* buffer);
  // Repair (rtp_camera_repair.cpp): each media packet and repair into rtpbin (after netsim),
  // the jitter buffer's input, and the budget applied from the bus thread.
  GstBuffer* on_media_into_rtpbin(GstBuffer* buffer);  // the buffer to pass on
  void on_new_jitter_buffer(GstElement* jitter_buffer);
  void apply_jitter_budget();
  // Immediate NACK (rtp_camera_nack.cpp).
  bool send_feedback(uint32_t media_ssrc, std::optional<uint16_t> nack_sequence);  // else PLI
  bool feedback_allowed(bool pli);  // the rate bounds
  void wire_immediate_nack(GstElement* rtx_receive);
  // ULP FEC (rtp_camera_fec.cpp): the decoder rtpbin asks for, and the wire's sequence number of
  // a packet the decoder renumbered.
  void wire_fec(GstElement* rtpbin);
  void wire_fec_decoder(GstElement* decoder);
  uint16_t wire_sequence(uint16_t depayloader_sequence) const;
  // udpsrc's arrival stamp of `buffer` on CLOCK_MONOTONIC (the pipeline clock), or now.
  int64_t arrival_ns(GstBuffer* buffer) const;
  // Reads the receive sockets' buffers and the kernel's drops into sockets_ (not the render
  // thread): after start, before a teardown (an error, stop) and in stats().
  void measure_sockets() const;

  RtpReceiveConfig config_;
  CameraFormat format_;  // negotiated: expected size, H.264 on the wire
  std::unique_ptr<Mailbox<Frame>> mailbox_;

  std::atomic<bool> running_{false};
  std::atomic<SourceState> state_{SourceState::kClosed};
  std::atomic<int64_t> last_frame_ns_{0};

  // Owned by the streaming thread.
  int learned_width_ = 0, learned_height_ = 0;
  uint64_t sequence_ = 0;
  int sized_slots_ = 0;
  RgbaConverter to_rgba_;
  AccessUnitPts access_unit_pts_;  // the depayloader's input thread

  RtpCameraCounters counters_;
  // The media SSRC, sequence numbers and RTP times taken (udpsrc's streaming thread, or
  // srtpdec's with a key: one thread either way).
  RtpStreamGuard stream_guard_;
  RtpFrameStamper stamper_;
  RtpCalibrationCache calibrations_;
  ViewFeedbackSchedule view_;
  std::mutex feedback_mutex_;
  std::string feedback_to_;  // feedback_mutex_: where feedback goes now ("" none yet)
  std::atomic<bool> feedback_known_{false};
  // feedback_mutex_: what send_feedback() sends through, taken when the pipeline is wired (the
  // RTCP udpsrc, whose socket it uses, and rtpbin's internal session 0, whose SSRC it signs
  // with). It runs in the jitter buffer's timer thread (a NACK) and the decoder's (a PLI), which
  // may hold GStreamer locks there: looking elements up in the pipeline from them deadlocked.
  GstElementPtr feedback_source_;
  GObjectPtr<GObject> feedback_session_;
  double nack_tokens_ = 64.0;  // feedback_mutex_: immediate NACKs allowed now
  int64_t nack_tokens_ns_ = 0, last_pli_ns_ = 0;
  std::atomic<uint32_t> media_ssrc_{0};  // the stream's SSRC (for an immediate PLI)
  // Set when a stalled camera that had shown video asked for a key frame; cleared by the next
  // published frame, so each outage asks once (more come from the depayloader on every loss).
  std::atomic<bool> key_frame_requested_{false};
  // Streaming thread (the decode queue's: depayloader, decoder and appsink run in it); reset by
  // wire() for each pipeline. Each access unit's verdict rides on it to its decoded frame
  // (access_unit_mark.h).
  H264HealWatch heal_;
  SpscRing<RtpFrameTiming, 1024> timings_;
  FormatWatch format_watch_;            // streaming thread; the station pops its events
  mutable ReceiveSocketWatch sockets_;  // measured from const stats() too: it locks itself
  uint32_t last_arrived_rtp_time_ = 0;  // udpsrc's thread: the newest frame's, for frames_arrived
  mutable std::mutex budget_mutex_;     // streaming thread adds, bus thread reads
  JitterBudget budget_;
  GstElement* jitter_buffer_ = nullptr;  // budget_mutex_: the stream's (ref held)
  std::atomic<int> latency_ms_{0};       // applied to the jitter buffer now
  std::shared_ptr<FrameEndRequester> frame_end_;
  // The FEC decoder's probes (the jitter buffer's thread): the wire's number of the packet in
  // it, whether it is rebuilding a lost one; and, by its number out, (wire << 16 | out).
  uint16_t fec_wire_sequence_ = 0;
  bool fec_rebuilding_ = false;
  std::array<std::atomic<uint32_t>, 1024> fec_sequences_{};
  // Last: destroyed first, so that its bus thread and probes never see a member gone.
  PipelineRunner pipeline_;
};

}  // namespace hd::drivers
