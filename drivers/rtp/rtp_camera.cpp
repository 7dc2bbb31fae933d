#include "drivers/rtp/rtp_camera.h"

#include <gio/gio.h>
#include <gst/app/gstappsink.h>
#include <gst/net/gstnetaddressmeta.h>
#include <gst/rtp/gstrtcpbuffer.h>
#include <gst/video/video.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <mutex>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/gstreamer_init.h"
#include "drivers/rtp/h264_payload.h"
#include "drivers/rtp/rtp_aux_bin.h"
#include "drivers/rtp/rtp_receive_pipeline.h"
#include "drivers/rtp/srtp_elements.h"
#include "drivers/rtp/view_feedback.h"

namespace hd::drivers {
namespace {

// The newest error message on `bus`, or "" (for a start() that failed).
std::string pending_error(GstElement* pipeline) {
  GstBus* bus = gst_element_get_bus(pipeline);
  std::string text;
  while (GstMessage* m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
    GError* e = nullptr;
    gst_message_parse_error(m, &e, nullptr);
    if (e != nullptr) text = e->message;
    g_clear_error(&e);
    gst_message_unref(m);
  }
  gst_object_unref(bus);
  return text;
}

// CLOCK_REALTIME - CLOCK_MONOTONIC now, ns (the two read back to back).
int64_t realtime_minus_monotonic_ns() {
  timespec r{}, m{};
  ::clock_gettime(CLOCK_REALTIME, &r);
  ::clock_gettime(CLOCK_MONOTONIC, &m);
  return (int64_t(r.tv_sec) - int64_t(m.tv_sec)) * 1'000'000'000LL +
         (int64_t(r.tv_nsec) - int64_t(m.tv_nsec));
}

}  // namespace

RtpCamera::RtpCamera(RtpReceiveConfig config)
    : config_(std::move(config)),
      mailbox_(std::make_unique<Mailbox<Frame>>()),
      stream_guard_(config_.stall_timeout_ns),
      clock_(config_.clock_drift_ppm) {
  format_.pixel_format = PixelFormat::kRgba8;
  if (config_.srtp_key) view_key_ = view_feedback_key(*config_.srtp_key);
}

RtpCamera::~RtpCamera() {
  stop();
  teardown();
}

std::string RtpCamera::pipeline_description() const {
  return receive_pipeline_description(config_);
}

void RtpCamera::open() {
  ensure_gstreamer();
  if (pipeline_ == nullptr) build();
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
      std::to_string(config_.jitter_buffer_latency_ms) + " ms, NACK " +
      (config_.retransmission ? "on" : "off") +
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
                        : std::string("; no encryption (no key_file)"));
  return n;
}

void RtpCamera::build() {
  feedback_to_.clear();  // a new pipeline's multiudpsink has no destination yet
  GError* error = nullptr;
  const std::string description = receive_pipeline_description(config_);
  GstElement* p = gst_parse_launch(description.c_str(), &error);
  if (p == nullptr || error != nullptr) {
    const std::string why = error != nullptr ? error->message : "unknown error";
    g_clear_error(&error);
    if (p != nullptr) gst_object_unref(p);
    throw DeviceError("camera " + id() + ": cannot build the receive pipeline: " + why);
  }
  pipeline_ = p;
  // Frame times are read on this clock: CLOCK_MONOTONIC, the station's one clock.
  GstClock* clock = GST_CLOCK(
      g_object_new(GST_TYPE_SYSTEM_CLOCK, "clock-type", GST_CLOCK_TYPE_MONOTONIC, nullptr));
  gst_pipeline_use_clock(GST_PIPELINE(pipeline_), clock);
  gst_object_unref(clock);

  {  // RTX: answer rtpbin's request for an aux receiver, then request the pad that asks for it
    GstElement* rtpbin = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtpBin);
    if (config_.retransmission)
      g_signal_connect(rtpbin, "request-aux-receiver",
                       G_CALLBACK(+[](GstElement*, guint session, gpointer self) {
                         auto* me = static_cast<RtpCamera*>(self);
                         return make_rtp_aux_bin(rtx_receive_description(me->config_), session);
                       }),
                       this);
    if (config_.retransmission)
      g_signal_connect(rtpbin, "new-jitterbuffer",
                       G_CALLBACK(+[](GstElement*, GstElement* jb, guint, guint, gpointer self) {
                         const RtpReceiveConfig& c = static_cast<RtpCamera*>(self)->config_;
                         // No timer for "the next packet is due": it is due one packet spacing
                         // after the last, an estimate the jitter buffer only corrects from a
                         // next packet that came in time. A sender whose packets once came fast
                         // (a burst, a fuzz's replay) taught it ~1 ms; each frame's first packet
                         // then came 33 ms later, after the 20 ms latency: declared lost, dropped
                         // as late, the frame lost, and the estimate never corrected (only key
                         // frames were shown). A loss is found from the gap the next packet
                         // leaves instead (rtx-delay-reorder).
                         g_object_set(jb, "rtx-delay", c.rtx_delay_ms, "rtx-delay-reorder",
                                      c.rtx_delay_reorder, "rtx-next-seqnum", FALSE, nullptr);
                       }),
                       this);
    GstElement* session = nullptr;  // session 0 exists: the RTCP pads created it
    g_signal_emit_by_name(rtpbin, "get-session", 0u, &session);
    if (session != nullptr) {
      g_object_set(session, "rtcp-fraction",
                   static_cast<gdouble>(config_.rtcp_bandwidth_bytes_per_s), nullptr);
      gst_object_unref(session);
    }
    const MediaLink from = receive_media_link(config_);
    GstElement* last = gst_bin_get_by_name(GST_BIN(pipeline_), from.element);
    const gboolean linked = gst_element_link_pads(last, from.pad, rtpbin, "recv_rtp_sink_0");
    gst_object_unref(last);
    gst_object_unref(rtpbin);
    GstElement* rtx = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtxReceive);
    const bool rtx_ok = !config_.retransmission || rtx != nullptr;
    if (rtx != nullptr) gst_object_unref(rtx);  // the pipeline keeps it; looked up by name
    if (!linked || !rtx_ok) {
      teardown();
      throw DeviceError("camera " + id() + ": cannot link the receive pipeline to rtpbin" +
                        (config_.retransmission ? " (with its RTX aux receiver)" : ""));
    }
  }

  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtpSource);
  GstPad* pad = gst_element_get_static_pad(src, "src");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, &RtpCamera::rtp_probe_cb, this, nullptr);
  gst_object_unref(pad);
  gst_object_unref(src);

  if (config_.srtp_key) {
    GstElement* dec = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kSrtpDecoder);
    answer_srtp_key_requests(dec, *config_.srtp_key);
    // The station's own RTCP (receiver reports, NACK, PLI, which ask the sender for work) is
    // SRTCP too: the sender takes only what this key protects.
    GstElement* enc = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kSrtpEncoder);
    set_srtp_encoder_key(enc, *config_.srtp_key);
    gst_object_unref(enc);
    GstPad* out = gst_element_get_static_pad(dec, "rtp_src");
    gst_pad_add_probe(
        out, GST_PAD_PROBE_TYPE_BUFFER,
        [](GstPad*, GstPadProbeInfo* info, gpointer self) {
          return static_cast<RtpCamera*>(self)->on_decrypted(GST_PAD_PROBE_INFO_BUFFER(info));
        },
        this, nullptr);
    gst_object_unref(out);
    gst_object_unref(dec);
  }

  {  // receiver reports often (each gives the sender a round trip); the sender reports going in
    GstElement* rtpbin = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtpBin);
    GObject* session = nullptr;
    g_signal_emit_by_name(rtpbin, "get-internal-session", 0u, &session);
    if (session != nullptr) {
      g_object_set(session, "rtcp-min-interval",
                   static_cast<guint64>(config_.rtcp_interval_ms) * GST_MSECOND, nullptr);
      g_object_unref(session);
    }
    GstPad* in = gst_element_get_static_pad(rtpbin, "recv_rtcp_sink_0");
    if (in != nullptr) {  // after srtpdec: the sender report is readable here
      gst_pad_add_probe(
          in, GST_PAD_PROBE_TYPE_BUFFER,
          [](GstPad*, GstPadProbeInfo* info, gpointer self) {
            static_cast<RtpCamera*>(self)->on_rtcp_into_rtpbin(GST_PAD_PROBE_INFO_BUFFER(info));
            return GST_PAD_PROBE_OK;
          },
          this, nullptr);
      gst_object_unref(in);
    }
    gst_object_unref(rtpbin);
  }
  {
    GstElement* dec = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kDecoder);
    GstPad* out = gst_element_get_static_pad(dec, "src");
    gst_pad_add_probe(
        out, GST_PAD_PROBE_TYPE_BUFFER,
        [](GstPad*, GstPadProbeInfo* info, gpointer self) {
          static_cast<RtpCamera*>(self)->on_decoded(GST_PAD_PROBE_INFO_BUFFER(info));
          return GST_PAD_PROBE_OK;
        },
        this, nullptr);
    gst_object_unref(out);
    gst_object_unref(dec);
  }

  GstElement* depay = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kDepayloader);
  pad = gst_element_get_static_pad(depay, "sink");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, &RtpCamera::depay_probe_cb, this, nullptr);
  gst_object_unref(pad);
  pad = gst_element_get_static_pad(depay, "src");  // access units: key frames are not delta units
  gst_pad_add_probe(
      pad, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        auto* me = static_cast<RtpCamera*>(self);
        GstBuffer* b = GST_PAD_PROBE_INFO_BUFFER(info);
        if (GST_BUFFER_FLAG_IS_SET(b, GST_BUFFER_FLAG_DELTA_UNIT)) return GST_PAD_PROBE_OK;
        int64_t capture = 0;
        {
          std::lock_guard lock(me->stamp_mutex_);
          for (const StampSlot& slot : me->stamps_)
            if (slot.pts == GST_BUFFER_PTS(b)) capture = slot.capture_mono_ns;
        }
        me->last_key_capture_ns_.store(capture, std::memory_order_relaxed);
        me->key_frames_.fetch_add(1, std::memory_order_release);
        return GST_PAD_PROBE_OK;
      },
      this, nullptr);
  gst_object_unref(pad);
  gst_object_unref(depay);

  // RTCP feedback (receiver reports, NACK, PLI) goes back to where the sender's RTCP comes from.
  GstElement* rtcp_src = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtcpSource);
  pad = gst_element_get_static_pad(rtcp_src, "src");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, &RtpCamera::rtcp_probe_cb, this, nullptr);
  gst_object_unref(pad);
  gst_object_unref(rtcp_src);

  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kAppSink);
  GstAppSinkCallbacks callbacks{};
  callbacks.new_sample = [](GstAppSink* s, gpointer self) {
    return RtpCamera::new_sample_cb(GST_ELEMENT(s), self);
  };
  gst_app_sink_set_callbacks(GST_APP_SINK(sink), &callbacks, this, nullptr);
  gst_object_unref(sink);
}

void RtpCamera::teardown() {
  if (pipeline_ == nullptr) return;
  gst_element_set_state(pipeline_, GST_STATE_NULL);
  gst_object_unref(pipeline_);
  pipeline_ = nullptr;
}

void RtpCamera::start() {
  if (running_) return;
  open();
  if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    const std::string why = pending_error(pipeline_);
    teardown();
    throw DeviceError("camera " + id() + ": cannot listen on " + config_.listen.host + ":" +
                      std::to_string(config_.listen.port) + ": " +
                      (why.empty() ? "the pipeline refused to start" : why));
  }
  last_frame_ns_.store(monotonic_now_ns(), std::memory_order_relaxed);
  // Nothing has arrived yet: stalled until the first frame (never streaming without video).
  state_.store(SourceState::kStalled, std::memory_order_release);
  running_ = true;
  bus_thread_ = std::thread([this] { bus_loop(); });
}

void RtpCamera::stop() {
  if (!running_.exchange(false)) return;
  if (bus_thread_.joinable()) bus_thread_.join();
  if (pipeline_ != nullptr) gst_element_set_state(pipeline_, GST_STATE_NULL);
  state_.store(SourceState::kClosed, std::memory_order_release);
}

void RtpCamera::bus_loop() {
  int64_t restart_at_ns = 0;
  while (running_.load(std::memory_order_relaxed)) {
    const int64_t now = monotonic_now_ns();
    if (pipeline_ == nullptr) {
      if (now >= restart_at_ns) {
        try {
          build();
          if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
            teardown();
            restart_at_ns = now + 500'000'000;
          } else {
            restarts_.fetch_add(1, std::memory_order_relaxed);
          }
        } catch (const DeviceError&) {
          restart_at_ns = now + 500'000'000;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // waiting to retry, not a sync
      continue;
    }
    GstBus* bus = gst_element_get_bus(pipeline_);
    GstMessage* m = gst_bus_timed_pop_filtered(
        bus, 100 * GST_MSECOND, static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_EOS));
    gst_object_unref(bus);
    if (m != nullptr) {
      std::string text = "end of stream";
      if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
        GError* e = nullptr;
        gchar* debug = nullptr;
        gst_message_parse_error(m, &e, &debug);
        text = std::string(GST_OBJECT_NAME(GST_MESSAGE_SRC(m))) + ": " +
               (e != nullptr ? e->message : "error");
        g_clear_error(&e);
        g_free(debug);
      }
      gst_message_unref(m);
      bus_errors_.fetch_add(1, std::memory_order_relaxed);
      {
        std::lock_guard lock(error_mutex_);
        last_error_ = text;
      }
      state_.store(SourceState::kDisconnected, std::memory_order_release);
      teardown();
      restart_at_ns = monotonic_now_ns() + 500'000'000;
      continue;
    }
    send_view_feedback();
    const SourceState s = state_.load(std::memory_order_acquire);
    if (s == SourceState::kStreaming &&
        monotonic_now_ns() - last_frame_ns_.load(std::memory_order_relaxed) >
            config_.stall_timeout_ns)
      state_.store(SourceState::kStalled, std::memory_order_release);
  }
}

// A retransmission carries the original sequence number before the original payload: checked
// as H.264 from there (the two bytes read as a NAL header would refuse nearly every repair).
RtpPacketError RtpCamera::check_payload(const RtpPacketView& view) const {
  return view.payload_type == config_.rtx_payload_type ? check_h264_rtx_payload(view.payload)
                                                       : check_h264_payload(view.payload);
}

int64_t RtpCamera::arrival_ns(GstBuffer* buffer) const {
  const int64_t now = monotonic_now_ns();
  GstClockTime t = GST_BUFFER_DTS(buffer);
  if (!GST_CLOCK_TIME_IS_VALID(t)) t = GST_BUFFER_PTS(buffer);
  const GstClockTime base = pipeline_ != nullptr ? gst_element_get_base_time(pipeline_) : 0;
  if (!GST_CLOCK_TIME_IS_VALID(t) || base == 0 || !GST_CLOCK_TIME_IS_VALID(base)) return now;
  const int64_t arrival = int64_t(t + base);
  return arrival <= now ? arrival : now;  // a stamp in the future is not an arrival
}

void RtpCamera::note_arrival(uint16_t sequence, int64_t arrival_ns) {
  const uint64_t us = arrival_ns > 0 ? uint64_t(arrival_ns) / 1000 : 0;
  arrivals_[sequence % arrivals_.size()].store((us << 16) | sequence, std::memory_order_relaxed);
}

int64_t RtpCamera::arrival_of(uint16_t sequence, int64_t now_ns) const {
  const uint64_t v = arrivals_[sequence % arrivals_.size()].load(std::memory_order_relaxed);
  if (v == 0 || uint16_t(v & 0xFFFF) != sequence) return 0;
  // Rounded down to the microsecond, so never after the moment udpsrc stamped it. An entry more
  // than a second old is of an earlier round of the numbers (or of a renumbered stream).
  const int64_t arrival = int64_t(v >> 16) * 1000;
  return arrival <= now_ns && now_ns - arrival < 1'000'000'000 ? arrival : 0;
}

RtpCamera::StampSlot& RtpCamera::stamp_slot(uint64_t pts, int64_t arrival_ns, int64_t now_ns) {
  for (StampSlot& s : stamps_)
    if (s.pts == pts) {  // a later packet of the frame (in the jitter buffer's order)
      if (arrival_ns != 0 && (s.arrival_ns == 0 || arrival_ns < s.arrival_ns))
        s.arrival_ns = arrival_ns;
      // Received when its last packet is through, as "sent" is its last packet's: the first
      // packet may be through before the last was even sent.
      s.received_ns = std::max(s.received_ns, now_ns);
      return s;
    }
  StampSlot& s = stamps_[stamp_next_];
  stamp_next_ = (stamp_next_ + 1) % stamps_.size();
  s = {};
  s.pts = pts;
  s.received_ns = now_ns;
  s.arrival_ns = arrival_ns;
  return s;
}

GstPadProbeReturn RtpCamera::rtp_probe_cb(GstPad*, GstPadProbeInfo* info, gpointer self) {
  return static_cast<RtpCamera*>(self)->on_rtp_packet(GST_PAD_PROBE_INFO_BUFFER(info));
}

GstPadProbeReturn RtpCamera::on_rtp_packet(GstBuffer* buffer) {
  packets_.fetch_add(1, std::memory_order_relaxed);
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return GST_PAD_PROBE_DROP;
  bytes_.fetch_add(map.size, std::memory_order_relaxed);
  RtpPacketView view;
  RtpPacketError e = parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view);
  if (e == RtpPacketError::kNone && view.payload_type != config_.payload_type &&
      view.payload_type != config_.rtx_payload_type)
    e = RtpPacketError::kOtherPayloadType;
  // With SRTP the payload is still encrypted here: on_decrypted() checks it.
  if (e == RtpPacketError::kNone && !config_.srtp_key) e = check_payload(view);
  // Last, so that only packets otherwise passed on move it: one media SSRC at a time, with
  // sequence numbers and RTP times its sender can send (RtpStreamGuard). With a key only
  // authenticated packets may move it: on_decrypted().
  if (e == RtpPacketError::kNone && view.payload_type == config_.payload_type &&
      !config_.srtp_key) {
    const int64_t arrival = arrival_ns(buffer);
    e = stream_guard_.check(view, arrival);
    stream_resyncs_.store(stream_guard_.resyncs(), std::memory_order_relaxed);
    if (e == RtpPacketError::kNone) note_arrival(view.sequence, arrival);
  }
  gst_buffer_unmap(buffer, &map);
  if (e != RtpPacketError::kNone) {
    malformed_[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
    return GST_PAD_PROBE_DROP;
  }
  well_formed_.fetch_add(1, std::memory_order_relaxed);
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn RtpCamera::on_decrypted(GstBuffer* buffer) {
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return GST_PAD_PROBE_DROP;
  RtpPacketView view;
  RtpPacketError e = parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view);
  if (e == RtpPacketError::kNone) e = check_payload(view);
  if (e == RtpPacketError::kNone && view.payload_type == config_.payload_type) {
    const int64_t arrival = arrival_ns(buffer);
    e = stream_guard_.check(view, arrival);
    stream_resyncs_.store(stream_guard_.resyncs(), std::memory_order_relaxed);
    if (e == RtpPacketError::kNone) note_arrival(view.sequence, arrival);
  }
  gst_buffer_unmap(buffer, &map);
  if (e != RtpPacketError::kNone) {  // authentic but malformed: counted as malformed only
    malformed_[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
    well_formed_.fetch_sub(1, std::memory_order_relaxed);
    return GST_PAD_PROBE_DROP;
  }
  decrypted_.fetch_add(1, std::memory_order_relaxed);
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn RtpCamera::rtcp_probe_cb(GstPad*, GstPadProbeInfo* info, gpointer self) {
  auto* me = static_cast<RtpCamera*>(self);
  GstNetAddressMeta* meta = gst_buffer_get_net_address_meta(GST_PAD_PROBE_INFO_BUFFER(info));
  if (meta == nullptr || !G_IS_INET_SOCKET_ADDRESS(meta->addr)) return GST_PAD_PROBE_OK;
  GInetSocketAddress* a = G_INET_SOCKET_ADDRESS(meta->addr);
  gchar* host = g_inet_address_to_string(g_inet_socket_address_get_address(a));
  const int port = g_inet_socket_address_get_port(a);
  const std::string where = std::string(host) + ":" + std::to_string(port);
  if (where != me->feedback_to_) {  // a new sender (or the first): feedback goes there now
    me->feedback_to_ = where;
    GstElement* sink = gst_bin_get_by_name(GST_BIN(me->pipeline_), rtp_elements::kRtcpSink);
    g_signal_emit_by_name(sink, "clear");
    g_signal_emit_by_name(sink, "add", host, port);
    gst_object_unref(sink);
    me->feedback_targets_.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard lock(me->view_mutex_);
    me->view_host_ = host;
    me->view_port_ = port;
    me->view_sent_ns_ = 0;  // a new sender hears the station's view at once
  }
  g_free(host);
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn RtpCamera::depay_probe_cb(GstPad* pad, GstPadProbeInfo* info, gpointer self) {
  auto* cam = static_cast<RtpCamera*>(self);
  // Packets again after a stall (a cut link, a sender that paused): the frames in between are
  // gone, so ask the sender for a key frame at once instead of waiting for its next one. A jitter
  // buffer that resynchronises after a long gap reports no loss, so the depayloader would not.
  if (cam->state_.load(std::memory_order_acquire) == SourceState::kStalled &&
      cam->frames_published_.load(std::memory_order_relaxed) > 0 &&
      !cam->key_frame_requested_.exchange(true, std::memory_order_acq_rel)) {
    cam->key_frame_requests_.fetch_add(1, std::memory_order_relaxed);
    gst_pad_push_event(pad,
                       gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
  }
  cam->on_depay_packet(GST_PAD_PROBE_INFO_BUFFER(info));
  return GST_PAD_PROBE_OK;
}

void RtpCamera::on_depay_packet(GstBuffer* buffer) {
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return;
  RtpPacketView view;
  RtpFrameStamp stamp;
  StampError e = StampError::kNoNtp;
  std::optional<StreamCalibration> calibration;
  CalibrationError ce = CalibrationError::kNone;
  const bool parsed =
      parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view) == RtpPacketError::kNone;
  if (parsed && view.has_extension) {
    e = read_frame_stamp(view, stamp);
    ce = read_packet_calibration(view, stamp.camera, calibration);
  }
  gst_buffer_unmap(buffer, &map);
  const GstClockTime pts = GST_BUFFER_PTS(buffer);
  const int64_t now = monotonic_now_ns();
  const bool timed = parsed && GST_CLOCK_TIME_IS_VALID(pts);
  const int64_t arrival = timed ? arrival_of(view.sequence, now) : 0;
  const bool extended = parsed && view.has_extension;  // else a plain sender: nothing to read
  if (extended && ce != CalibrationError::kNone)
    calibration_errors_[static_cast<std::size_t>(ce)].fetch_add(1, std::memory_order_relaxed);
  else if (extended && calibration)
    calibrations_received_.fetch_add(1, std::memory_order_relaxed);
  const bool stamped = extended && e == StampError::kNone;
  if (extended && !stamped)
    stamp_errors_[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
  if (stamped && stamp.camera) {
    last_camera_index_.store(stamp.camera->camera_index, std::memory_order_relaxed);
    last_revision_.store(stamp.camera->calibration_revision, std::memory_order_relaxed);
  }
  if (stamped && stamp.stages && stamp.stages->round_trip_count != 0 &&
      stamp.stages->round_trip_count != last_round_trip_count_) {  // a new round trip
    last_round_trip_count_ = stamp.stages->round_trip_count;
    std::lock_guard lock(clock_mutex_);
    clock_.add_round_trip(int64_t(stamp.stages->round_trip_us) * 1000);
  }
  const ClockMapping m = stamped && timed ? clock_mapping() : ClockMapping{};
  std::lock_guard lock(stamp_mutex_);  // the calibrations and the frame's slot, in one go
  if (extended && ce == CalibrationError::kNone && calibration) {
    if (!calibrations_[0] || calibrations_[0]->revision != calibration->revision) {
      for (std::size_t i = calibrations_.size() - 1; i > 0; --i)
        calibrations_[i] = calibrations_[i - 1];
    }
    calibrations_[0] = calibration;
  }
  if (!timed) return;
  StampSlot& slot = stamp_slot(pts, arrival, now);  // every packet: when its frame came in
  if (!stamped) return;
  // The frame was sent with its last packet: each later one's stamp replaces the earlier.
  slot.capture_mono_ns = *stamp.capture_unix_ns + m.offset_ns;
  if (stamp.stages) {
    slot.encoded_ns = slot.capture_mono_ns + int64_t(stamp.stages->encoded_us) * 1000;
    slot.sent_ns =
        std::max(slot.sent_ns, slot.capture_mono_ns + int64_t(stamp.stages->sent_us) * 1000);
  } else {
    slot.encoded_ns = 0;
  }
  slot.uncertainty_ns = m.uncertainty_ns;
  slot.has_revision = stamp.camera.has_value();
  slot.revision = slot.has_revision ? stamp.camera->calibration_revision : 0;
}

ClockMapping RtpCamera::clock_mapping() const {
  if (config_.clock == RtpReceiveConfig::Clock::kSynchronized) {
    ClockMapping m;
    m.kind = ClockMapping::Kind::kSynchronized;
    m.offset_ns = -realtime_minus_monotonic_ns();
    m.uncertainty_ns = config_.clock_error_ns;
    return m;
  }
  ClockMapping m;
  {
    std::lock_guard lock(clock_mutex_);
    m = clock_.mapping(monotonic_now_ns());
  }
  if (m.kind == ClockMapping::Kind::kUnmeasured) m.offset_ns = -realtime_minus_monotonic_ns();
  return m;
}

// RTCP into rtpbin (after srtpdec): each sender report is a sample of the sender's clock against
// its arrival here (udpsrc's arrival stamp on the pipeline clock, CLOCK_MONOTONIC).
void RtpCamera::on_rtcp_into_rtpbin(GstBuffer* buffer) {
  const int64_t now = monotonic_now_ns();
  int64_t arrival = now;
  const GstClockTime pts = GST_BUFFER_PTS(buffer);
  const GstClockTime base = pipeline_ != nullptr ? gst_element_get_base_time(pipeline_) : 0;
  if (GST_CLOCK_TIME_IS_VALID(pts) && base != 0 && int64_t(pts + base) <= now)
    arrival = int64_t(pts + base);
  GstRTCPBuffer rtcp = GST_RTCP_BUFFER_INIT;
  if (!gst_rtcp_buffer_validate_reduced(buffer) ||
      !gst_rtcp_buffer_map(buffer, GST_MAP_READ, &rtcp))
    return;
  GstRTCPPacket packet;
  for (gboolean more = gst_rtcp_buffer_get_first_packet(&rtcp, &packet); more;
       more = gst_rtcp_packet_move_to_next(&packet)) {
    if (gst_rtcp_packet_get_type(&packet) != GST_RTCP_TYPE_SR) continue;
    guint32 ssrc = 0, rtptime = 0, packets = 0, octets = 0;
    guint64 ntp = 0;
    gst_rtcp_packet_sr_get_sender_info(&packet, &ssrc, &ntp, &rtptime, &packets, &octets);
    const auto sent = ntp64_to_unix_ns(ntp);
    if (!sent) continue;
    sender_reports_.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard lock(clock_mutex_);
    clock_.add_sender_report(*sent, arrival);
  }
  gst_rtcp_buffer_unmap(&rtcp);
}

void RtpCamera::on_decoded(GstBuffer* buffer) {
  const GstClockTime pts = GST_BUFFER_PTS(buffer);
  if (!GST_CLOCK_TIME_IS_VALID(pts)) return;
  const int64_t now = monotonic_now_ns();
  std::lock_guard lock(stamp_mutex_);
  for (StampSlot& s : stamps_)
    if (s.pts == pts) {
      s.decoded_ns = now;
      return;
    }
  // A frame whose packets left no slot (gone from the ring): one for its decode time only.
  StampSlot& slot = stamps_[stamp_next_];
  stamp_next_ = (stamp_next_ + 1) % stamps_.size();
  slot = {};
  slot.pts = pts;
  slot.decoded_ns = now;
}

GstFlowReturn RtpCamera::new_sample_cb(GstElement* sink, gpointer self) {
  static_cast<RtpCamera*>(self)->on_sample(sink);
  return GST_FLOW_OK;
}

void RtpCamera::on_sample(GstElement* sink) {
  GstSample* sample = gst_app_sink_pull_sample(GST_APP_SINK(sink));
  if (sample == nullptr) return;
  const int64_t now = monotonic_now_ns();
  GstVideoInfo info;
  GstBuffer* buffer = gst_sample_get_buffer(sample);
  GstCaps* caps = gst_sample_get_caps(sample);
  if (buffer == nullptr || caps == nullptr || !gst_video_info_from_caps(&info, caps)) {
    gst_sample_unref(sample);
    return;
  }
  const int w = GST_VIDEO_INFO_WIDTH(&info), h = GST_VIDEO_INFO_HEIGHT(&info);
  if (learned_width_ == 0 && !format_.known()) {
    learned_width_ = w;
    learned_height_ = h;
  }
  const int want_w = format_.known() ? format_.width_px : learned_width_;
  const int want_h = format_.known() ? format_.height_px : learned_height_;
  CameraFormat expected = format_;
  expected.width_px = want_w;
  expected.height_px = want_h;
  if (w != want_w || h != want_h) {
    wrong_format_.fetch_add(1, std::memory_order_relaxed);
    state_.store(SourceState::kFormatMismatch, std::memory_order_release);
    format_watch_.lost(now, FormatEventCause::kFrame, expected,
                       CameraFormat{w, h, PixelFormat::kRgba8, 0.0});
    gst_sample_unref(sample);
    return;
  }
  format_watch_.restored(now, FormatEventCause::kFrame, expected);
  GstVideoFrame vf;
  if (!gst_video_frame_map(&vf, &info, buffer, GST_MAP_READ)) {
    gst_sample_unref(sample);
    return;
  }
  Frame& slot = mailbox_->write_slot();
  // Only the first three frames of a stream whose size was not negotiated size a slot.
  if (slot.width != w || slot.height != h || slot.data.size() != std::size_t(w) * h * 4) {
    slot.allocate_rgba(w, h);
    ++sized_slots_;
  }
  const uint8_t* src = static_cast<const uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&vf, 0));
  const int src_stride = GST_VIDEO_FRAME_PLANE_STRIDE(&vf, 0);
  for (int y = 0; y < h; ++y)
    std::memcpy(slot.data.data() + std::size_t(y) * slot.stride_bytes,
                src + std::size_t(y) * src_stride, std::size_t(w) * 4);
  gst_video_frame_unmap(&vf);
  const GstClockTime pts = GST_BUFFER_PTS(buffer);
  int64_t capture_ns = 0;
  bool stamped = false;
  slot.calibration = {};
  StampSlot stages;
  if (GST_CLOCK_TIME_IS_VALID(pts)) {
    std::lock_guard lock(stamp_mutex_);
    for (const StampSlot& s : stamps_)
      if (s.pts == pts) {
        stages = s;
        capture_ns = s.capture_mono_ns;
        stamped = s.capture_mono_ns != 0;
        if (!s.has_revision) continue;
        for (const std::optional<StreamCalibration>& c : calibrations_)
          if (c && c->revision == s.revision) {
            slot.calibration = {true, c->revision, c->p_c, c->T_world_cam};
            break;
          }
      }
  }
  // Arrival: udpsrc's stamp of the frame's earliest packet. Not the buffer's PTS: the jitter
  // buffer's skew-smoothed output time may lie after the frame was even decoded (a capture or
  // decode time before "arrival" was seen under load). Without one (a frame of retransmissions
  // only), the moment its last packet reached the depayloader, which is after its arrival.
  int64_t arrival_ns = now;
  if (stages.arrival_ns != 0 && stages.arrival_ns <= now)
    arrival_ns = stages.arrival_ns;
  else if (stages.received_ns != 0 && stages.received_ns <= now)
    arrival_ns = stages.received_ns;
  if (slot.calibration.present &&
      (slot.calibration.p_c.width != w || slot.calibration.p_c.height != h)) {
    calibration_size_mismatch_.fetch_add(1, std::memory_order_relaxed);
    gst_sample_unref(sample);
    return;
  }
  if (stamped && capture_ns > arrival_ns) {
    capture_after_arrival_.fetch_add(1, std::memory_order_relaxed);
    capture_ns = arrival_ns;
  }
  if ((stamped ? capture_ns : arrival_ns) <= last_published_capture_ns_) {
    not_newer_.fetch_add(1, std::memory_order_relaxed);
    gst_sample_unref(sample);
    return;
  }
  last_published_capture_ns_ = stamped ? capture_ns : arrival_ns;
  slot.sequence = ++sequence_;
  if (stamped) {
    stamped_.fetch_add(1, std::memory_order_relaxed);
    slot.host_timestamp_ns = capture_ns;
    slot.device_timestamp_ns = capture_ns;
    slot.device_time_trusted = true;
  } else {
    unstamped_.fetch_add(1, std::memory_order_relaxed);
    slot.host_timestamp_ns = arrival_ns;
    slot.device_timestamp_ns = arrival_ns;
    slot.device_time_trusted = false;
  }
  slot.link.encoded_ns = stamped ? stages.encoded_ns : 0;
  slot.link.sent_ns = stamped ? stages.sent_ns : 0;
  slot.link.received_ns = stages.received_ns;
  slot.link.decoded_ns = stages.decoded_ns;
  gst_sample_unref(sample);
  const bool calibrated = slot.calibration.present;
  mailbox_->publish();
  frames_published_.fetch_add(1, std::memory_order_relaxed);
  if (calibrated) frames_with_calibration_.fetch_add(1, std::memory_order_relaxed);
  key_frame_requested_.store(false, std::memory_order_release);
  RtpFrameTiming timing;
  timing.sequence = sequence_;
  timing.capture_ns = stamped ? capture_ns : arrival_ns;
  timing.encoded_ns = stamped ? stages.encoded_ns : 0;
  timing.sent_ns = stamped ? stages.sent_ns : 0;
  timing.arrival_ns = arrival_ns;
  timing.received_ns = stages.received_ns;
  timing.decoded_ns = stages.decoded_ns;
  timing.published_ns = monotonic_now_ns();
  timing.clock_uncertainty_ns = stamped ? stages.uncertainty_ns : 0;
  timing.stamped = stamped;
  timings_.push(timing);
  last_frame_ns_.store(now, std::memory_order_relaxed);
  state_.store(SourceState::kStreaming, std::memory_order_release);
}

RtpCamera::Feedback RtpCamera::feedback() const {
  Feedback f;
  f.key_frame_requests = key_frame_requests_.load(std::memory_order_relaxed);
  f.view_feedback_sent = view_sent_.load(std::memory_order_relaxed);
  if (pipeline_ == nullptr) return f;
  if (GstElement* rtx = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtxReceive)) {
    guint requests = 0, packets = 0;
    g_object_get(rtx, "num-rtx-requests", &requests, "num-rtx-packets", &packets, nullptr);
    gst_object_unref(rtx);
    f.rtx_requested = requests;
    f.rtx_received = packets;
  }
  GstElement* rtpbin = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtpBin);
  GObject* session = nullptr;
  g_signal_emit_by_name(rtpbin, "get-internal-session", 0u, &session);
  gst_object_unref(rtpbin);
  if (session == nullptr) return f;
  GstStructure* stats = nullptr;
  g_object_get(session, "stats", &stats, nullptr);
  g_object_unref(session);
  if (stats == nullptr) return f;
  const GValue* sources = gst_structure_get_value(stats, "source-stats");
  // rtpsession's "source-stats" is a GValueArray (deprecated in GLib, still what 1.22 returns).
  G_GNUC_BEGIN_IGNORE_DEPRECATIONS
  if (sources != nullptr && G_VALUE_HOLDS(sources, g_value_array_get_type())) {
    GValueArray* array = static_cast<GValueArray*>(g_value_get_boxed(sources));
    for (guint i = 0; array != nullptr && i < array->n_values; ++i) {
      const GstStructure* src = gst_value_get_structure(g_value_array_get_nth(array, i));
      gboolean internal = TRUE, have_sr = FALSE;
      gst_structure_get_boolean(src, "internal", &internal);
      if (internal) continue;  // our own source
      guint pli = 0, nack = 0;
      gst_structure_get_uint(src, "sent-pli-count", &pli);
      gst_structure_get_uint(src, "sent-nack-count", &nack);
      gst_structure_get_boolean(src, "have-sr", &have_sr);
      f.pli_sent += pli;
      f.nack_sent += nack;
      f.rtcp_received_from_sender += have_sr ? 1 : 0;
    }
  }
  G_GNUC_END_IGNORE_DEPRECATIONS
  gst_structure_free(stats);
  return f;
}

void RtpCamera::set_view_needed(bool needed) {
  view_need_.store(needed ? 1 : 0, std::memory_order_relaxed);
}

// Bus thread: the pipeline (and its RTCP socket) is stable here.
void RtpCamera::send_view_feedback() {
  const int need = view_need_.load(std::memory_order_relaxed);
  std::lock_guard lock(view_mutex_);
  const int64_t now = monotonic_now_ns();
  // A change goes out at once (this thread's next turn, <= 100 ms), the same state every 0.5 s
  // (the sender falls back to full rate after 2 s without any).
  if (need < 0 || view_port_ == 0 || pipeline_ == nullptr ||
      (need == view_sent_need_ && view_sent_ns_ != 0 && now - view_sent_ns_ < 500'000'000))
    return;
  GstElement* src = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kRtcpSource);
  GSocket* socket = nullptr;
  g_object_get(src, "used-socket", &socket, nullptr);
  gst_object_unref(src);
  if (socket == nullptr) return;
  GSocketAddress* to = g_inet_socket_address_new_from_string(view_host_.c_str(), view_port_);
  // With the stream's key the message carries a tag, so that nobody else can lower a camera.
  uint8_t packet[kAuthenticatedViewFeedbackSize];
  const ViewFeedback message{0, need == 1, ++view_sequence_};
  if (view_key_)
    write_view_feedback(message, *view_key_,
                        std::span<uint8_t, kAuthenticatedViewFeedbackSize>(packet));
  else
    write_view_feedback(message, std::span<uint8_t, kViewFeedbackSize>(packet, kViewFeedbackSize));
  const std::size_t size = view_key_ ? kAuthenticatedViewFeedbackSize : kViewFeedbackSize;
  if (to != nullptr && g_socket_send_to(socket, to, reinterpret_cast<const gchar*>(packet), size,
                                        nullptr, nullptr) == gssize(size))
    view_sent_.fetch_add(1, std::memory_order_relaxed);
  view_sent_ns_ = now;
  view_sent_need_ = need;
  if (to != nullptr) g_object_unref(to);
  g_object_unref(socket);
}

bool RtpCamera::request_key_frame() {
  if (pipeline_ == nullptr) return false;
  GstElement* depay = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kDepayloader);
  GstPad* pad = gst_element_get_static_pad(depay, "sink");
  const gboolean sent = gst_pad_push_event(
      pad, gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
  gst_object_unref(pad);
  gst_object_unref(depay);
  if (sent) key_frame_requests_.fetch_add(1, std::memory_order_relaxed);
  return sent;
}

bool RtpCamera::set_netsim_drop_probability(double p) {
  if (pipeline_ == nullptr || !config_.netsim()) return false;
  GstElement* n = gst_bin_get_by_name(GST_BIN(pipeline_), rtp_elements::kNetsim);
  if (n == nullptr) return false;
  g_object_set(n, "drop-probability", static_cast<gfloat>(p), nullptr);
  gst_object_unref(n);
  return true;
}

uint64_t RtpCamera::dropped_frames() const {
  return wrong_format_.load(std::memory_order_relaxed);
}

RtpCameraStats RtpCamera::stats() const {
  RtpCameraStats s;
  s.packets = packets_.load(std::memory_order_relaxed);
  s.bytes = bytes_.load(std::memory_order_relaxed);
  s.feedback_targets = feedback_targets_.load(std::memory_order_relaxed);
  for (std::size_t i = 0; i < s.malformed.size(); ++i) {
    s.malformed[i] = malformed_[i].load(std::memory_order_relaxed);
    s.malformed_total += s.malformed[i];
  }
  s.accepted = well_formed_.load(std::memory_order_relaxed);
  s.sequence_resyncs = stream_resyncs_.load(std::memory_order_relaxed);
  s.frames_published = frames_published_.load(std::memory_order_relaxed);
  s.wrong_format = wrong_format_.load(std::memory_order_relaxed);
  s.bus_errors = bus_errors_.load(std::memory_order_relaxed);
  s.restarts = restarts_.load(std::memory_order_relaxed);
  s.key_frames = key_frames_.load(std::memory_order_acquire);
  s.last_key_frame_capture_ns = last_key_capture_ns_.load(std::memory_order_relaxed);
  s.stamped_frames = stamped_.load(std::memory_order_relaxed);
  s.unstamped_frames = unstamped_.load(std::memory_order_relaxed);
  s.capture_after_arrival = capture_after_arrival_.load(std::memory_order_relaxed);
  s.not_newer = not_newer_.load(std::memory_order_relaxed);
  for (std::size_t i = 0; i < s.stamp_errors.size(); ++i)
    s.stamp_errors[i] = stamp_errors_[i].load(std::memory_order_relaxed);
  if (config_.srtp_key) {
    s.srtp_decrypted = decrypted_.load(std::memory_order_relaxed);
    const uint64_t in = well_formed_.load(std::memory_order_relaxed);
    // Packets in srtpdec's hands a moment ago count as neither: rejected never grows from them.
    s.srtp_rejected = in > s.srtp_decrypted ? in - s.srtp_decrypted : 0;
  }
  for (std::size_t i = 0; i < s.calibration_errors.size(); ++i) {
    s.calibration_errors[i] = calibration_errors_[i].load(std::memory_order_relaxed);
    s.calibration_errors_total += s.calibration_errors[i];
  }
  s.calibrations_received = calibrations_received_.load(std::memory_order_relaxed);
  s.frames_with_calibration = frames_with_calibration_.load(std::memory_order_relaxed);
  s.calibration_size_mismatch = calibration_size_mismatch_.load(std::memory_order_relaxed);
  {
    std::lock_guard lock(stamp_mutex_);
    s.calibration = calibrations_[0];
  }
  s.last_camera_index = last_camera_index_.load(std::memory_order_relaxed);
  s.last_calibration_revision = last_revision_.load(std::memory_order_relaxed);
  s.sender_reports = sender_reports_.load(std::memory_order_relaxed);
  s.clock = clock_mapping();
  std::lock_guard lock(error_mutex_);
  s.last_error = last_error_;
  return s;
}

}  // namespace hd::drivers
