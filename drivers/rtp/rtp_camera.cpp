// RtpCamera: its life (open, negotiate, start, stop) and what its probes do with each packet and
// frame. The pipeline's wiring is in rtp_camera_wiring.cpp, its RTCP side in rtp_camera_rtcp.cpp,
// its counters in rtp_link_report.cpp.
#include "drivers/rtp/rtp_camera.h"

#include <gst/app/gstappsink.h>
#include <gst/video/video.h>

#include <cstring>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/gobject_ptr.h"
#include "drivers/rtp/access_unit_mark.h"
#include "drivers/rtp/gstreamer_init.h"
#include "drivers/rtp/h264_payload.h"
#include "drivers/rtp/h264_recovery_point.h"
#include "drivers/rtp/rtp_receive_pipeline.h"

namespace hd::drivers {
namespace {

std::optional<ViewFeedbackKey> view_key_of(const RtpReceiveConfig& c) {
  if (!c.srtp_key) return std::nullopt;
  return view_feedback_key(*c.srtp_key);
}

JitterBudget::Settings budget_settings(const RtpReceiveConfig& c) {
  JitterBudget::Settings s;
  s.min_ms = c.jitter_buffer_latency_ms;
  s.max_ms = std::max(c.jitter_buffer_latency_ms, c.jitter_buffer_max_ms);
  s.start_ms = initial_latency_ms(c);
  s.retransmission = c.retransmission;
  return s;
}

}  // namespace

RtpCamera::RtpCamera(RtpReceiveConfig config)
    : config_(std::move(config)),
      mailbox_(std::make_unique<Mailbox<Frame>>()),
      stream_guard_(config_.stall_timeout_ns),
      stamper_(config_),
      view_(view_key_of(config_)),
      sockets_(config_.receive_buffer_bytes, config_.rtcp_receive_buffer_bytes),
      budget_(budget_settings(config_)),
      latency_ms_(initial_latency_ms(config_)),
      frame_end_(FrameEndRequester::create({})),
      pipeline_({"camera " + to_uri(config_.listen), "receive pipeline",
                 receive_pipeline_description(config_)},
                {[this](PipelineRunner& p) { wire(p); },
                 [this](const std::string&) { on_bus_error(); }, [this] { on_bus_turn(); }}) {
  format_.pixel_format = PixelFormat::kRgba8;
}

RtpCamera::~RtpCamera() {
  stop();
  frame_end_->shutdown();
  pipeline_.teardown();
  std::lock_guard lock(budget_mutex_);
  if (jitter_buffer_ != nullptr) gst_object_unref(jitter_buffer_);
}

std::string RtpCamera::pipeline_description() const {
  return receive_pipeline_description(config_);
}

void RtpCamera::open() {
  ensure_gstreamer();
  pipeline_.build();
}

FormatNegotiation RtpCamera::negotiate(const CameraFormatRequest& wanted) {
  if (running_) throw DeviceError("camera " + id() + ": negotiate() after start()");
  if (wanted.width_px > 0 && wanted.height_px > 0) {
    format_.width_px = wanted.width_px;
    format_.height_px = wanted.height_px;
    Frame prototype;
    prototype.allocate_rgba(wanted.width_px, wanted.height_px);
    mailbox_ = std::make_unique<Mailbox<Frame>>(prototype);
    sized_slots_ = 3;
  }
  open();
  FormatNegotiation n;
  n.delivered = format_;
  n.delivered.width_px = 0;  // a stream cannot be asked for a size: known at its first frame
  n.delivered.height_px = 0;
  n.detail =
      "RTP H.264 listening on " + config_.listen.host + ":" + std::to_string(config_.listen.port) +
      " (RTCP " + std::to_string(config_.listen.port + 1) + "), jitter buffer " +
      (config_.jitter_buffer_auto
           ? "sized from the link, " + std::to_string(config_.jitter_buffer_latency_ms) + ".." +
                 std::to_string(config_.jitter_buffer_max_ms)
           : std::to_string(config_.jitter_buffer_latency_ms)) +
      " ms, NACK " + (config_.retransmission ? "on" : "off") + ", ULP FEC " +
      (config_.fec ? "rebuilt when the sender sends it (payload type " +
                         std::to_string(config_.fec_payload_type) + ")"
                   : std::string("refused")) +
      "; p_c from the station's calibration file for a plain sender, p_c and P_c from the "
      "stream when its sender sends them (hybrid-remote); capture time = arrival time for a "
      "plain RTP sender (it stamps none), the sender's ntp-64 stamp for hybrid-remote, " +
      (config_.clock == RtpReceiveConfig::Clock::kSynchronized
           ? "mapped through this host's CLOCK_REALTIME (clock: synchronized, stated error " +
                 std::to_string(config_.clock_error_ns / 1000) + " us)"
           : std::string("mapped through the offset measured from its RTCP sender reports and "
                         "round trip (until measured: this host's CLOCK_REALTIME, exact on one "
                         "host only)")) +
      (config_.srtp_key ? "; SRTP AES-128-GCM required (key file " + config_.srtp_key->file + ")"
                        : std::string("; no encryption (no key_file)")) +
      // Measured now on a socket of its own (the pipeline's open at start), set as udpsrc will:
      // this process, this kernel, these limits.
      "; RTP receive buffer " +
      socket_buffer_text(probe_socket_buffer(config_.receive_buffer_bytes));
  return n;
}

void RtpCamera::start() {
  if (running_) return;
  ensure_gstreamer();
  std::string why;
  if (!pipeline_.play(why)) {
    throw DeviceError("camera " + id() + ": cannot listen on " + config_.listen.host + ":" +
                      std::to_string(config_.listen.port) + ": " +
                      (why.empty() ? "the pipeline refused to start" : why));
  }
  measure_sockets();  // what udpsrc got (its sockets open when the pipeline plays)
  last_frame_ns_.store(monotonic_now_ns(), std::memory_order_relaxed);
  // Nothing has arrived yet: stalled until the first frame (never streaming without video).
  state_.store(SourceState::kStalled, std::memory_order_release);
  running_ = true;
  pipeline_.start();
}

void RtpCamera::stop() {
  if (!running_.exchange(false)) return;
  measure_sockets();  // the kernel's last drop count: the sockets close with the pipeline
  pipeline_.stop();
  state_.store(SourceState::kClosed, std::memory_order_release);
}

void RtpCamera::on_bus_error() {
  measure_sockets();  // before the teardown closes them
  state_.store(SourceState::kDisconnected, std::memory_order_release);
}

void RtpCamera::on_bus_turn() {
  send_view_feedback();
  apply_jitter_budget();
  const SourceState s = state_.load(std::memory_order_acquire);
  if (s == SourceState::kStreaming &&
      monotonic_now_ns() - last_frame_ns_.load(std::memory_order_relaxed) >
          config_.stall_timeout_ns)
    state_.store(SourceState::kStalled, std::memory_order_release);
}

// A retransmission carries the original sequence number before the original payload: checked
// as H.264 from there (the two bytes read as a NAL header would refuse nearly every repair).
RtpPacketError RtpCamera::check_payload(const RtpPacketView& view) const {
  if (is_fec(view.payload_type)) {
    // A 10-byte FEC header and a level header of at least 4 (RFC 5109 7.3, 7.4), after a
    // repair's 2-byte original sequence number; rtpulpfecdec checks what they say.
    const std::size_t least = view.payload_type == config_.fec_payload_type ? 14 : 16;
    return view.payload.size() >= least ? RtpPacketError::kNone : RtpPacketError::kFecTooShort;
  }
  return view.payload_type == config_.rtx_payload_type ? check_h264_rtx_payload(view.payload)
                                                       : check_h264_payload(view.payload);
}

// One media SSRC at a time, with sequence numbers and RTP times its sender can send
// (RtpStreamGuard); the arrival of each packet taken, for its frame's arrival time.
RtpPacketError RtpCamera::check_stream(const RtpPacketView& view, GstBuffer* buffer) {
  // FEC shares the media's SSRC and sequence numbers: the guard takes it too, but it is no
  // frame of its own.
  const bool fec = config_.fec && view.payload_type == config_.fec_payload_type;
  if (view.payload_type != config_.payload_type && !fec) return RtpPacketError::kNone;  // RTX
  const int64_t arrival = arrival_ns(buffer);
  const RtpPacketError e = stream_guard_.check(view, arrival);
  counters_.sequence_resyncs.store(stream_guard_.resyncs(), std::memory_order_relaxed);
  if (e == RtpPacketError::kNone && fec)
    counters_.fec_packets.fetch_add(1, std::memory_order_relaxed);
  if (e == RtpPacketError::kNone && !fec) {
    stamper_.note_arrival(view.sequence, arrival);
    // A frame's packets share its RTP time and come together: a new time is a frame that
    // reached this host (counted before any fault injection; what was sent, for the shares).
    if (view.timestamp != last_arrived_rtp_time_ ||
        counters_.frames_arrived.load(std::memory_order_relaxed) == 0) {
      last_arrived_rtp_time_ = view.timestamp;
      counters_.frames_arrived.fetch_add(1, std::memory_order_relaxed);
    }
  }
  return e;
}

int64_t RtpCamera::arrival_ns(GstBuffer* buffer) const {
  const int64_t now = monotonic_now_ns();
  GstClockTime t = GST_BUFFER_DTS(buffer);
  if (!GST_CLOCK_TIME_IS_VALID(t)) t = GST_BUFFER_PTS(buffer);
  const GstClockTime base = pipeline_.base_time();
  if (!GST_CLOCK_TIME_IS_VALID(t) || base == 0 || !GST_CLOCK_TIME_IS_VALID(base)) return now;
  const int64_t arrival = int64_t(t + base);
  return arrival <= now ? arrival : now;  // a stamp in the future is not an arrival
}

GstPadProbeReturn RtpCamera::on_rtp_packet(GstBuffer* buffer) {
  counters_.packets.fetch_add(1, std::memory_order_relaxed);
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return GST_PAD_PROBE_DROP;
  counters_.bytes.fetch_add(map.size, std::memory_order_relaxed);
  RtpPacketView view;
  RtpPacketError e = parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view);
  if (e == RtpPacketError::kNone && view.payload_type != config_.payload_type &&
      view.payload_type != config_.rtx_payload_type && !is_fec(view.payload_type))
    e = RtpPacketError::kOtherPayloadType;
  // With SRTP the payload is still encrypted here, and only authenticated packets may move the
  // stream guard: on_decrypted() checks both. Last, so that only packets otherwise passed on
  // move it.
  if (e == RtpPacketError::kNone && !config_.srtp_key) e = check_payload(view);
  if (e == RtpPacketError::kNone && !config_.srtp_key) e = check_stream(view, buffer);
  gst_buffer_unmap(buffer, &map);
  if (e != RtpPacketError::kNone) {
    counters_.count(e);
    return GST_PAD_PROBE_DROP;
  }
  counters_.accepted.fetch_add(1, std::memory_order_relaxed);
  if (!config_.srtp_key) set_feedback_target(buffer, false);
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn RtpCamera::on_decrypted(GstBuffer* buffer) {
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return GST_PAD_PROBE_DROP;
  RtpPacketView view;
  RtpPacketError e = parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view);
  if (e == RtpPacketError::kNone) e = check_payload(view);
  if (e == RtpPacketError::kNone) e = check_stream(view, buffer);
  gst_buffer_unmap(buffer, &map);
  if (e != RtpPacketError::kNone) {  // authentic but malformed: counted as malformed only
    counters_.count(e);
    counters_.accepted.fetch_sub(1, std::memory_order_relaxed);
    return GST_PAD_PROBE_DROP;
  }
  counters_.decrypted.fetch_add(1, std::memory_order_relaxed);
  set_feedback_target(buffer, false);  // authenticated: only the key's holder moves it
  return GST_PAD_PROBE_OK;
}

// The depayloader's input, after the jitter buffer. Packets again after a stall (a cut link, a
// sender that paused): the frames in between are gone, so ask the sender for a key frame at once
// instead of waiting for its next one. A jitter buffer that resynchronises after a long gap
// reports no loss, so the depayloader would not. Not for a stream that heals by intra refresh: its
// frames are withheld for up to two sweeps after a loss (a stall, while packets flow), and
// x264enc answers with another sweep, not an IDR.
void RtpCamera::on_depay_packet(GstPad* pad, GstBuffer*& buffer) {
  counters_.packets_depayloaded.fetch_add(1, std::memory_order_relaxed);
  if (state_.load(std::memory_order_acquire) == SourceState::kStalled &&
      !heal_.heals_by_refresh() && counters_.frames_published.load(std::memory_order_relaxed) > 0 &&
      !key_frame_requested_.exchange(true, std::memory_order_acq_rel)) {
    counters_.key_frame_requests.fetch_add(1, std::memory_order_relaxed);
    gst_pad_push_event(pad,
                       gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
  }
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return;
  RtpPacketView view;
  RtpFrameStamp stamp;
  StampError e = StampError::kNoNtp;
  std::optional<StreamCalibration> calibration;
  CalibrationError ce = CalibrationError::kNone;
  const bool parsed =
      parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view) == RtpPacketError::kNone;
  const bool extended = parsed && view.has_extension;  // else a plain sender: nothing to read
  const bool starts_picture = parsed && h264_payload_starts_picture(view.payload);
  if (extended) {
    e = read_frame_stamp(view, stamp);
    ce = read_packet_calibration(view, stamp.camera, calibration);
  }
  gst_buffer_unmap(buffer, &map);
  if (!parsed) return;
  const int64_t now = monotonic_now_ns();
  // Before the frame's slot names its revision: a frame that names one finds it.
  if (extended && ce != CalibrationError::kNone)
    calibrations_.refuse(ce);
  else if (extended && calibration)
    calibrations_.add(*calibration);
  const bool stamped = extended && e == StampError::kNone;
  if (extended && !stamped) counters_.count(e);
  if (stamped && stamp.camera) {
    counters_.last_camera_index.store(stamp.camera->camera_index, std::memory_order_relaxed);
    counters_.last_calibration_revision.store(stamp.camera->calibration_revision,
                                              std::memory_order_relaxed);
  }
  GstClockTime pts = GST_BUFFER_PTS(buffer);
  if (GST_CLOCK_TIME_IS_VALID(pts)) {  // one PTS per access unit, which the stamper keys on
    const uint64_t unique = access_unit_pts_.next(view.timestamp, pts);
    if (unique != pts) {
      buffer = gst_buffer_make_writable(buffer);
      GST_BUFFER_PTS(buffer) = unique;
      pts = unique;
      counters_.access_units_retimed.store(access_unit_pts_.nudged(), std::memory_order_relaxed);
    }
  }
  stamper_.add_packet(GST_CLOCK_TIME_IS_VALID(pts) ? std::optional<uint64_t>(pts) : std::nullopt,
                      wire_sequence(view.sequence), stamped ? &stamp : nullptr, now);
  heal_.packet(view.sequence, pts, view.marker, starts_picture);
}

// The depayloader's output: access units, where key frames are not delta units.
bool RtpCamera::on_access_unit(GstPad* pad, GstBuffer*& buffer) {
  counters_.access_units.fetch_add(1, std::memory_order_relaxed);
  if (!judge_access_unit(pad, buffer)) return false;
  if (GST_BUFFER_FLAG_IS_SET(buffer, GST_BUFFER_FLAG_DELTA_UNIT)) return true;
  counters_.last_key_frame_capture_ns.store(stamper_.capture_of(GST_BUFFER_PTS(buffer)),
                                            std::memory_order_relaxed);
  counters_.key_frames.fetch_add(1, std::memory_order_release);
  return true;
}

void RtpCamera::on_decoded(GstBuffer* buffer) {
  counters_.frames_decoded.fetch_add(1, std::memory_order_relaxed);
  const std::optional<AccessUnitMark> mark = access_unit_mark(buffer);
  if (mark && GST_CLOCK_TIME_IS_VALID(mark->pts))
    stamper_.add_decoded(mark->pts, monotonic_now_ns());
}

// The appsink's streaming thread: no allocation here once the mailbox's slots are sized and the
// converter built (once per decoder format).
void RtpCamera::on_sample(GstElement* sink) {
  const GstSamplePtr sample(gst_app_sink_pull_sample(GST_APP_SINK(sink)));
  if (!sample) return;
  counters_.frames_converted.fetch_add(1, std::memory_order_relaxed);
  const int64_t now = monotonic_now_ns();
  GstVideoInfo info;
  GstBuffer* buffer = gst_sample_get_buffer(sample.get());  // borrowed from the sample
  GstCaps* caps = gst_sample_get_caps(sample.get());        // likewise
  if (buffer == nullptr || caps == nullptr || !gst_video_info_from_caps(&info, caps)) return;
  const int w = GST_VIDEO_INFO_WIDTH(&info), h = GST_VIDEO_INFO_HEIGHT(&info);
  if (learned_width_ == 0 && !format_.known()) {
    learned_width_ = w;
    learned_height_ = h;
  }
  CameraFormat expected = format_;
  expected.width_px = format_.known() ? format_.width_px : learned_width_;
  expected.height_px = format_.known() ? format_.height_px : learned_height_;
  if (w != expected.width_px || h != expected.height_px) {
    counters_.wrong_format.fetch_add(1, std::memory_order_relaxed);
    state_.store(SourceState::kFormatMismatch, std::memory_order_release);
    format_watch_.lost(now, FormatEventCause::kFrame, expected,
                       CameraFormat{w, h, PixelFormat::kRgba8, 0.0});
    return;
  }
  format_watch_.restored(now, FormatEventCause::kFrame, expected);
  // A part of it, or of its references, is missing; or it is not known which access unit it is.
  const std::optional<AccessUnitMark> mark = access_unit_mark(buffer);
  if (!mark || !mark->whole) {
    (mark ? counters_.frames_damaged : counters_.frames_without_verdict)
        .fetch_add(1, std::memory_order_relaxed);
    return;
  }
  GstVideoFrame vf;
  if (!gst_video_frame_map(&vf, &info, buffer, GST_MAP_READ)) return;
  Frame& slot = mailbox_->write_slot();
  // Only the first three frames of a stream whose size was not negotiated size a slot.
  if (slot.width != w || slot.height != h || slot.data.size() != std::size_t(w) * h * 4) {
    slot.allocate_rgba(w, h);
    ++sized_slots_;
  }
  const bool converted = to_rgba_.to_rgba(&vf, slot);
  gst_video_frame_unmap(&vf);
  if (!converted) {
    counters_.wrong_format.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  const RtpStampedFrame t = stamper_.frame(
      GST_CLOCK_TIME_IS_VALID(mark->pts) ? std::optional<uint64_t>(mark->pts) : std::nullopt, now);
  slot.calibration =
      t.stages.has_revision ? calibrations_.lookup(t.stages.revision) : FrameCalibration{};
  if (!calibrations_.fits(slot.calibration, w, h)) return;
  if (t.capture_after_arrival)
    counters_.capture_after_arrival.fetch_add(1, std::memory_order_relaxed);
  if (!stamper_.admit(t)) {
    counters_.not_newer.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  slot.sequence = ++sequence_;
  (t.stamped ? counters_.stamped : counters_.unstamped).fetch_add(1, std::memory_order_relaxed);
  slot.host_timestamp_ns = t.capture_ns;
  slot.device_timestamp_ns = t.capture_ns;
  slot.device_time_trusted = t.stamped;
  slot.link.encoded_ns = t.stamped ? t.stages.encoded_ns : 0;
  slot.link.sent_ns = t.stamped ? t.stages.sent_ns : 0;
  slot.link.received_ns = t.stages.received_ns;
  slot.link.decoded_ns = t.stages.decoded_ns;
  const bool calibrated = slot.calibration.present;
  const int64_t encoded_ns = slot.link.encoded_ns, sent_ns = slot.link.sent_ns;
  mailbox_->publish();  // the slot is the reader's from here
  counters_.frames_published.fetch_add(1, std::memory_order_relaxed);
  calibrations_.count_published(calibrated);
  key_frame_requested_.store(false, std::memory_order_release);
  RtpFrameTiming timing;
  timing.sequence = sequence_;
  timing.capture_ns = t.capture_ns;
  timing.encoded_ns = encoded_ns;
  timing.sent_ns = sent_ns;
  timing.arrival_ns = t.arrival_ns;
  timing.received_ns = t.stages.received_ns;
  timing.decoded_ns = t.stages.decoded_ns;
  timing.published_ns = monotonic_now_ns();
  timing.clock_uncertainty_ns = t.stamped ? t.stages.uncertainty_ns : 0;
  timing.stamped = t.stamped;
  timings_.push(timing);
  last_frame_ns_.store(now, std::memory_order_relaxed);
  state_.store(SourceState::kStreaming, std::memory_order_release);
}

bool RtpCamera::set_netsim_drop_probability(double p) {
  if (!config_.netsim()) return false;
  const GstElementPtr n = pipeline_.find(rtp_elements::kNetsim);
  if (!n) return false;
  g_object_set(n.get(), "drop-probability", static_cast<gfloat>(p), nullptr);
  return true;
}

}  // namespace hd::drivers
