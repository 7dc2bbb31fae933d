#include "remote/sender/rtp_sender.h"

#include <gio/gio.h>
#include <gst/app/gstappsrc.h>
#include <gst/rtp/gstrtcpbuffer.h>
#include <gst/rtp/rtp.h>
#include <gst/video/video.h>
#include <time.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/clock_offset_estimator.h"
#include "drivers/rtp/gstreamer_init.h"
#include "drivers/rtp/rtp_aux_bin.h"
#include "drivers/rtp/rtp_frame_stamp.h"
#include "drivers/rtp/srtp_elements.h"
#include "remote/sender/rtp_send_pipeline.h"

namespace hd::remote {
namespace {

using drivers::realtime_minus_monotonic_ns;

GstElement* by_name(GstElement* pipeline, const char* name) {
  return gst_bin_get_by_name(GST_BIN(pipeline), name);
}

uint32_t micros_between(int64_t from_ns, int64_t to_ns) {
  const int64_t us = (to_ns - from_ns) / 1000;
  return us < 0 ? 0u : us > int64_t(UINT32_MAX) ? UINT32_MAX : static_cast<uint32_t>(us);
}

}  // namespace

RtpSender::RtpSender(RtpSendConfig config)
    : config_(std::move(config)), revision_(config_.calibration_revision) {
  if (config_.srtp_key) view_key_ = drivers::view_feedback_key(*config_.srtp_key);
  if (config_.p_c && !set_calibration(*config_.p_c, config_.T_world_cam, false))
    throw std::invalid_argument(
        "stream to " + config_.host + ":" + std::to_string(config_.port) +
        ": the calibration cannot be sent (not a valid pinhole and rotation, or a distortion "
        "count other than 0, 4, 5 or 8)");
}

bool RtpSender::set_calibration(const core::Pinhole& p_c, const core::Pose& T_world_cam) {
  return set_calibration(p_c, T_world_cam, true);
}

bool RtpSender::set_calibration(const core::Pinhole& p_c, const core::Pose& T_world_cam,
                                bool next_revision) {
  drivers::StreamCalibration c;
  c.camera_index = config_.camera_index;
  c.revision = revision_.load() + (next_revision ? 1u : 0u);
  c.p_c = p_c;
  c.T_world_cam = T_world_cam;
  std::array<uint8_t, drivers::kCalibrationMaxSize> bytes{};
  const std::size_t n = drivers::write_calibration(c, bytes);
  if (n == 0) return false;
  std::lock_guard lock(calibration_mutex_);
  calibration_element_ = bytes;
  calibration_size_ = n;
  revision_.store(c.revision, std::memory_order_release);
  return true;
}

RtpSender::~RtpSender() {
  stop();
  if (ntp_caps_ != nullptr) gst_caps_unref(ntp_caps_);
  if (appsrc_ != nullptr) gst_object_unref(appsrc_);
  if (rtxsend_ != nullptr) gst_object_unref(rtxsend_);
  if (pipeline_ != nullptr) gst_object_unref(pipeline_);
}

std::string RtpSender::description() const {
  return send_pipeline_description(config_);
}

void RtpSender::start() {
  if (playing_) return;
  drivers::ensure_gstreamer();
  const std::string where = config_.host + ":" + std::to_string(config_.port);
  if (pipeline_ == nullptr) {
    GError* error = nullptr;
    pipeline_ = gst_parse_launch(description().c_str(), &error);
    if (pipeline_ == nullptr || error != nullptr) {
      const std::string why = error != nullptr ? error->message : "unknown error";
      g_clear_error(&error);
      throw std::runtime_error("stream to " + where + ": cannot build the pipeline: " + why);
    }
    GstClock* clock = GST_CLOCK(
        g_object_new(GST_TYPE_SYSTEM_CLOCK, "clock-type", GST_CLOCK_TYPE_MONOTONIC, nullptr));
    gst_pipeline_use_clock(GST_PIPELINE(pipeline_), clock);
    gst_object_unref(clock);
    appsrc_ = by_name(pipeline_, send_elements::kAppSource);
    {  // push() converts each RGBA frame into appsrc's format (no videoconvert, no copy)
      GstCaps* caps = gst_app_src_get_caps(GST_APP_SRC(appsrc_));
      const bool ok = input_.configure(caps);
      if (caps != nullptr) gst_caps_unref(caps);
      if (!ok)
        throw std::runtime_error("stream to " + where +
                                 ": cannot make buffers of the encoder's input format");
    }
    ntp_caps_ = gst_caps_new_empty_simple("timestamp/x-ntp");

    if (config_.srtp_key) {
      GstElement* enc = by_name(pipeline_, send_elements::kSrtpEncoder);
      drivers::set_srtp_encoder_key(enc, *config_.srtp_key);
      gst_object_unref(enc);
      GstElement* dec = by_name(pipeline_, send_elements::kSrtcpDecoder);
      drivers::answer_srtp_key_requests(dec, *config_.srtp_key);
      gst_object_unref(dec);
    }
    {  // one socket for RTP out and RTCP out and in: the station answers to where our RTP and
       // RTCP come from, so it can ask for a lost packet from the first packet on, not only
       // after our first sender report (symmetric RTP, RFC 4961)
      GstElement* in = by_name(pipeline_, send_elements::kRtcpIn);
      GstElement* out = by_name(pipeline_, send_elements::kRtcpOut);
      GstElement* rtp_out = by_name(pipeline_, send_elements::kRtpOut);
      gst_element_set_state(in, GST_STATE_READY);
      GSocket* socket = nullptr;
      g_object_get(in, "used-socket", &socket, nullptr);
      if (socket != nullptr) {
        g_object_set(out, "socket", socket, "close-socket", FALSE, nullptr);
        g_object_set(rtp_out, "socket", socket, "close-socket", FALSE, nullptr);
        if (GSocketAddress* local = g_socket_get_local_address(socket, nullptr)) {
          rtcp_port_ = g_inet_socket_address_get_port(G_INET_SOCKET_ADDRESS(local));
          g_object_unref(local);
        }
        g_object_unref(socket);
      }
      // The station's view feedback arrives here beside its RTCP: read and taken out before
      // rtpbin (a lone APP packet is no valid compound RTCP for it) and before the round-trip
      // probe below (added later, so called later).
      GstPad* in_src = gst_element_get_static_pad(in, "src");
      gst_pad_add_probe(
          in_src, GST_PAD_PROBE_TYPE_BUFFER,
          [](GstPad*, GstPadProbeInfo* info, gpointer self) {
            return static_cast<RtpSender*>(self)->on_view_feedback(GST_PAD_PROBE_INFO_BUFFER(info));
          },
          this, nullptr);
      gst_object_unref(in_src);
      gst_object_unref(in);
      gst_object_unref(out);
      gst_object_unref(rtp_out);
    }
    GstElement* rtpbin = by_name(pipeline_, send_elements::kRtpBin);
    {  // sender reports often enough for the station's clock estimate
      GObject* session = nullptr;
      g_signal_emit_by_name(rtpbin, "get-internal-session", 0u, &session);
      if (session != nullptr) {
        g_object_set(session, "rtcp-min-interval",
                     static_cast<guint64>(config_.rtcp_interval_ms) * GST_MSECOND, nullptr);
        g_object_unref(session);
      }
      GstPad* out = gst_element_get_static_pad(rtpbin, "send_rtcp_src_0");
      if (out != nullptr) {
        gst_pad_add_probe(
            out, GST_PAD_PROBE_TYPE_BUFFER,
            [](GstPad*, GstPadProbeInfo* info, gpointer self) {
              return static_cast<RtpSender*>(self)->on_rtcp_out(info);
            },
            this, nullptr);
        gst_object_unref(out);
      }
    }
    gst_object_unref(rtpbin);
    {  // the station's receiver reports: the round trip (before rtpbin, which keeps its own;
       // after srtpdec, which makes them readable)
      GstElement* in = by_name(
          pipeline_, config_.srtp_key ? send_elements::kSrtcpDecoder : send_elements::kRtcpIn);
      GstPad* pad = gst_element_get_static_pad(in, config_.srtp_key ? "rtcp_src" : "src");
      gst_pad_add_probe(
          pad, GST_PAD_PROBE_TYPE_BUFFER,
          [](GstPad*, GstPadProbeInfo* info, gpointer self) {
            return static_cast<RtpSender*>(self)->on_rtcp_in(GST_PAD_PROBE_INFO_BUFFER(info));
          },
          this, nullptr);
      gst_object_unref(pad);
      gst_object_unref(in);
    }
    GstElement* pay = by_name(pipeline_, send_elements::kPayloader);
    {  // RTX: answer rtpbin's request for an aux sender, then request the pad that asks for it
      GstElement* rtpbin = by_name(pipeline_, send_elements::kRtpBin);
      if (config_.retransmission)
        g_signal_connect(rtpbin, "request-aux-sender",
                         G_CALLBACK(+[](GstElement*, guint session, gpointer self) {
                           auto* me = static_cast<RtpSender*>(self);
                           return drivers::make_rtp_aux_bin(rtx_send_description(me->config_),
                                                            session);
                         }),
                         this);
      if (config_.fec_percentage > 0)
        g_signal_connect(rtpbin, "request-fec-encoder",
                         G_CALLBACK(+[](GstElement*, guint, gpointer self) {
                           return make_fec_encoder(static_cast<RtpSender*>(self)->config_);
                         }),
                         this);
      const gboolean linked = gst_element_link_pads(pay, "src", rtpbin, "send_rtp_sink_0");
      gst_object_unref(rtpbin);
      if (!linked)
        throw std::runtime_error("stream to " + where + ": cannot link the payloader to rtpbin" +
                                 (config_.retransmission ? " (with its RTX aux sender)" : ""));
      if (config_.retransmission) rtxsend_ = by_name(pipeline_, send_elements::kRtxSend);
      if (config_.retransmission && rtxsend_ == nullptr)
        throw std::runtime_error("stream to " + where + ": rtpbin took no RTX aux sender");
      GstElement* fec = by_name(pipeline_, send_elements::kFecEncoder);
      const bool fec_ok = (fec != nullptr) == (config_.fec_percentage > 0);
      if (fec != nullptr) gst_object_unref(fec);
      if (!fec_ok)
        throw std::runtime_error("stream to " + where +
                                 ": rtpbin took no FEC encoder (rtpulpfecenc, gst-plugins-good)");
    }
    GstElement* ntp = gst_element_factory_make("rtphdrextntp64", nullptr);
    if (ntp == nullptr)
      throw std::runtime_error("stream to " + where +
                               ": GStreamer has no rtphdrextntp64 (gst-plugins-good 1.22)");
    g_object_set(ntp, "every-packet", TRUE, nullptr);
    gst_rtp_header_extension_set_id(GST_RTP_HEADER_EXTENSION(ntp), drivers::kNtp64ExtensionId);
    g_signal_emit_by_name(pay, "add-extension", ntp);
    gst_object_unref(ntp);
    GstPad* sink = gst_element_get_static_pad(pay, "sink");
    gst_pad_add_probe(
        sink, GST_PAD_PROBE_TYPE_BUFFER,
        [](GstPad*, GstPadProbeInfo* info, gpointer self) {
          return static_cast<RtpSender*>(self)->on_encoded(info);
        },
        this, nullptr);
    gst_object_unref(sink);
    GstPad* src = gst_element_get_static_pad(pay, "src");
    gst_pad_add_probe(
        src,
        static_cast<GstPadProbeType>(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST),
        [](GstPad*, GstPadProbeInfo* info, gpointer self) {
          return static_cast<RtpSender*>(self)->on_packets(info);
        },
        this, nullptr);
    gst_object_unref(src);
    gst_object_unref(pay);
  }
  if (gst_element_set_state(pipeline_, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE)
    throw std::runtime_error("stream to " + where + ": the pipeline refused to start");
  base_time_ = gst_element_get_base_time(pipeline_);
  playing_ = true;
}

void RtpSender::stop() {
  if (!playing_) return;
  playing_ = false;
  gst_element_set_state(pipeline_, GST_STATE_NULL);
}

bool RtpSender::push(const drivers::Frame& f) {
  if (!playing_ || f.width != config_.width_px || f.height != config_.height_px ||
      f.format != drivers::PixelFormat::kRgba8) {
    refused_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  base_time_ = gst_element_get_base_time(pipeline_);
  const int64_t running = f.host_timestamp_ns - static_cast<int64_t>(base_time_);
  if (base_time_ == 0 || running < 0) {  // captured before the pipeline ran: no honest PTS
    refused_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  const bool needed = needed_now(drivers::monotonic_now_ns());
  needed_reported_.store(needed, std::memory_order_relaxed);
  if (needed && !was_needed_) {
    // Needed again: this frame becomes a key frame, so the station decodes at once instead of
    // waiting for the periodic one (key_int_frames frames, which at the low rate is divider
    // times longer).
    GstElement* enc = by_name(pipeline_, send_elements::kEncoder);
    gst_element_send_event(
        enc, gst_video_event_new_upstream_force_key_unit(GST_CLOCK_TIME_NONE, TRUE, 0));
    gst_object_unref(enc);
    forced_.fetch_add(1, std::memory_order_relaxed);
  }
  if (!needed && was_needed_) push_index_ = 0;  // the first low-rate frame goes at once
  was_needed_ = needed;
  if (!needed && push_index_++ % uint64_t(std::max(1, config_.low_rate_divider)) != 0) {
    skipped_.fetch_add(1, std::memory_order_relaxed);
    return true;  // taken, not sent: the station does not need every frame of this camera
  }
  GstBuffer* b = input_.convert(f);
  if (b == nullptr) {
    refused_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  GST_BUFFER_PTS(b) = static_cast<GstClockTime>(running);
  GST_BUFFER_DURATION(b) = static_cast<GstClockTime>(1e9 / config_.rate_hz);
  // The capture time on CLOCK_REALTIME, ns since the NTP epoch (rtphdrextntp64's input).
  gst_buffer_add_reference_timestamp_meta(
      b, ntp_caps_,
      static_cast<GstClockTime>(f.host_timestamp_ns + realtime_minus_monotonic_ns() +
                                config_.test_clock_shift_ns +
                                drivers::kNtpUnixOffsetS * 1'000'000'000LL),
      GST_CLOCK_TIME_NONE);
  gst_app_src_push_buffer(GST_APP_SRC(appsrc_), b);  // takes the buffer
  pushed_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

// The encoded frame, before the payloader: the capture time push() attached (a reference
// timestamp meta, which x264enc carries over) is what rtphdrextntp64 writes.
GstPadProbeReturn RtpSender::on_encoded(GstPadProbeInfo* info) {
  GstBuffer* b = GST_PAD_PROBE_INFO_BUFFER(info);
  const uint64_t index = frames_encoded_.fetch_add(1, std::memory_order_relaxed);
  if (!GST_BUFFER_FLAG_IS_SET(b, GST_BUFFER_FLAG_DELTA_UNIT)) {
    last_key_frame_index_.store(index, std::memory_order_relaxed);
    key_frames_.fetch_add(1, std::memory_order_release);
  }
  encoded_pts_ = GST_BUFFER_PTS(b);
  encoded_mono_ns_ = drivers::monotonic_now_ns();
  encoded_capture_ns_ = 0;
  // x264enc shifts its output PTS (by 1000 h, its min-pts), so the capture time comes from the
  // meta: back from CLOCK_REALTIME (+ the test shift) in the NTP epoch to CLOCK_MONOTONIC.
  if (const GstReferenceTimestampMeta* m = gst_buffer_get_reference_timestamp_meta(b, ntp_caps_)) {
    frames_stamped_.fetch_add(1, std::memory_order_relaxed);
    encoded_capture_ns_ = static_cast<int64_t>(m->timestamp) -
                          drivers::kNtpUnixOffsetS * 1'000'000'000LL -
                          realtime_minus_monotonic_ns() - config_.test_clock_shift_ns;
  }
  return GST_PAD_PROBE_OK;
}

bool RtpSender::stamp_packet(GstBuffer* buffer) {
  GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
  if (!gst_rtp_buffer_map(buffer, GST_MAP_READWRITE, &rtp)) return false;
  uint8_t data[drivers::kCameraStateSize];
  std::lock_guard lock(calibration_mutex_);  // the revision and its element go together
  drivers::write_camera_state({config_.camera_index, revision_.load(std::memory_order_relaxed)},
                              std::span<uint8_t, drivers::kCameraStateSize>(data));
  bool ok = gst_rtp_buffer_add_extension_onebyte_header(&rtp, drivers::kCameraStateExtensionId,
                                                        data, sizeof data);
  // Stage times after capture, for the packets of the frame on_encoded() saw last (the
  // payloader sends a frame's packets before it takes the next frame).
  const GstClockTime pts = GST_BUFFER_PTS(buffer);
  if (GST_CLOCK_TIME_IS_VALID(pts) && pts == encoded_pts_ && encoded_capture_ns_ != 0) {
    const int64_t capture_ns = encoded_capture_ns_;
    const int64_t now = drivers::monotonic_now_ns();
    drivers::SenderStagesStamp st;
    st.encoded_us = micros_between(capture_ns, encoded_mono_ns_);
    st.sent_us = micros_between(capture_ns, now);
    const uint64_t trips = round_trips_.load(std::memory_order_relaxed);
    const int64_t rtt = round_trip_ns_.load(std::memory_order_relaxed);
    // The count wraps past 255 to 1: 0 means "none measured yet".
    st.round_trip_count = trips == 0 ? 0 : static_cast<uint8_t>((trips - 1) % 255 + 1);
    st.round_trip_us = rtt < 0 ? 0u : micros_between(0, rtt);
    uint8_t stages[drivers::kSenderStagesSize];
    drivers::write_sender_stages(st, std::span<uint8_t, drivers::kSenderStagesSize>(stages));
    ok = gst_rtp_buffer_add_extension_onebyte_header(&rtp, drivers::kSenderStagesExtensionId,
                                                     stages, sizeof stages) &&
         ok;
  }
  if (ok) packets_stamped_.fetch_add(1, std::memory_order_relaxed);
  // Last: the calibration turns the packet's elements into the two-byte form.
  if (ok && calibration_size_ > 0 && gst_rtp_buffer_get_marker(&rtp)) {
    ok = add_calibration(rtp);
    if (ok) packets_calibrated_.fetch_add(1, std::memory_order_relaxed);
  }
  gst_rtp_buffer_unmap(&rtp);
  return ok;
}

// The depayloaders of GStreamer 1.22 read the last packet of a frame, and the station reads every
// packet: the calibration (140..204 bytes, over the one-byte form's 16) goes on the marker packet
// only, in the two-byte form, with the packet's one-byte elements rewritten in that form.
bool RtpSender::add_calibration(GstRTPBuffer& rtp) {
  guint16 bits = 0;
  gpointer data = nullptr;
  guint words = 0;
  if (!gst_rtp_buffer_get_extension_data(&rtp, &bits, &data, &words) || bits != 0xBEDE)
    return false;
  std::array<uint8_t, 1024> block{};
  const std::size_t n = drivers::to_two_byte_block(
      std::span<const uint8_t>(static_cast<const uint8_t*>(data), std::size_t(words) * 4),
      drivers::kCalibrationExtensionId,
      std::span<const uint8_t>(calibration_element_.data(), calibration_size_), block);
  if (n == 0 || !gst_rtp_buffer_set_extension_data(&rtp, 0x1000, static_cast<guint16>(n / 4)))
    return false;
  if (!gst_rtp_buffer_get_extension_data(&rtp, &bits, &data, &words) || words * 4 != n)
    return false;
  std::memcpy(data, block.data(), n);
  return true;
}

GstPadProbeReturn RtpSender::on_packets(GstPadProbeInfo* info) {
  if (GST_PAD_PROBE_INFO_TYPE(info) & GST_PAD_PROBE_TYPE_BUFFER_LIST) {
    GstBufferList* list = gst_buffer_list_make_writable(GST_PAD_PROBE_INFO_BUFFER_LIST(info));
    GST_PAD_PROBE_INFO_DATA(info) = list;
    for (guint i = 0; i < gst_buffer_list_length(list); ++i)
      stamp_packet(gst_buffer_list_get_writable(list, i));
  } else {
    GstBuffer* b = gst_buffer_make_writable(GST_PAD_PROBE_INFO_BUFFER(info));
    GST_PAD_PROBE_INFO_DATA(info) = b;
    stamp_packet(b);
  }
  return GST_PAD_PROBE_OK;
}

bool RtpSender::needed_now(int64_t now_ns) const {
  if (!config_.follow_view) return true;
  const int64_t last = last_feedback_ns_.load(std::memory_order_acquire);
  if (last == 0 || now_ns - last > static_cast<int64_t>(config_.view_feedback_timeout_s * 1e9))
    return true;  // no station that says otherwise: full rate
  return station_needs_.load(std::memory_order_relaxed);
}

GstPadProbeReturn RtpSender::on_view_feedback(GstBuffer* buffer) {
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return GST_PAD_PROBE_OK;
  drivers::ViewFeedback f;
  const drivers::ViewFeedbackError e = drivers::parse_view_feedback(
      std::span<const uint8_t>(map.data, map.size), view_key_ ? &*view_key_ : nullptr, f);
  gst_buffer_unmap(buffer, &map);
  if (e == drivers::ViewFeedbackError::kNotViewFeedback) return GST_PAD_PROBE_OK;  // RTCP
  if (e != drivers::ViewFeedbackError::kNone) {
    feedback_malformed_[static_cast<std::size_t>(e)].fetch_add(1, std::memory_order_relaxed);
    return GST_PAD_PROBE_DROP;
  }
  // A message older than the last one (reordered on the way) says nothing new.
  // After a silence (a restarted station counts from 0 again) any message is taken.
  const int64_t now = drivers::monotonic_now_ns();
  const int last = last_sequence_.load(std::memory_order_relaxed);
  const int64_t heard = last_feedback_ns_.load(std::memory_order_relaxed);
  const bool silence =
      heard == 0 || now - heard > static_cast<int64_t>(config_.view_feedback_timeout_s * 1e9);
  if (!silence && last >= 0 && static_cast<int16_t>(f.sequence - static_cast<uint16_t>(last)) <= 0)
    return GST_PAD_PROBE_DROP;
  last_sequence_.store(f.sequence, std::memory_order_relaxed);
  station_needs_.store(f.needed, std::memory_order_relaxed);
  last_feedback_ns_.store(now, std::memory_order_release);
  feedback_received_.fetch_add(1, std::memory_order_relaxed);
  return GST_PAD_PROBE_DROP;
}

int64_t RtpSender::sender_realtime_ns() const {
  return drivers::monotonic_now_ns() + realtime_minus_monotonic_ns() + config_.test_clock_shift_ns;
}

// rtpbin's RTCP on its way out: count the sender reports, and with a test clock shift move their
// NTP time by it (rtpsession reads the host's CLOCK_REALTIME itself).
GstPadProbeReturn RtpSender::on_rtcp_out(GstPadProbeInfo* info) {
  GstBuffer* b = GST_PAD_PROBE_INFO_BUFFER(info);
  const bool shift = config_.test_clock_shift_ns != 0;
  if (shift) {
    b = gst_buffer_make_writable(b);
    GST_PAD_PROBE_INFO_DATA(info) = b;
  }
  GstRTCPBuffer rtcp = GST_RTCP_BUFFER_INIT;
  if (!gst_rtcp_buffer_map(b, shift ? GST_MAP_READWRITE : GST_MAP_READ, &rtcp))
    return GST_PAD_PROBE_OK;
  GstRTCPPacket packet;
  for (gboolean more = gst_rtcp_buffer_get_first_packet(&rtcp, &packet); more;
       more = gst_rtcp_packet_move_to_next(&packet)) {
    if (gst_rtcp_packet_get_type(&packet) != GST_RTCP_TYPE_SR) continue;
    sender_reports_.fetch_add(1, std::memory_order_relaxed);
    if (!shift) continue;
    guint32 ssrc = 0, rtptime = 0, packets = 0, octets = 0;
    guint64 ntp = 0;
    gst_rtcp_packet_sr_get_sender_info(&packet, &ssrc, &ntp, &rtptime, &packets, &octets);
    if (const auto unix_ns = drivers::ntp64_to_unix_ns(ntp))
      gst_rtcp_packet_sr_set_sender_info(
          &packet, ssrc, drivers::unix_ns_to_ntp64(*unix_ns + config_.test_clock_shift_ns), rtptime,
          packets, octets);
  }
  gst_rtcp_buffer_unmap(&rtcp);
  return GST_PAD_PROBE_OK;
}

// The station's RTCP: each report block about our stream gives a round trip (RFC 3550 A.8) on
// the clock of our sender reports.
GstPadProbeReturn RtpSender::on_rtcp_in(GstBuffer* buffer) {
  const uint32_t arrival = drivers::compact_ntp(sender_realtime_ns());
  GstRTCPBuffer rtcp = GST_RTCP_BUFFER_INIT;
  if (!gst_rtcp_buffer_validate_reduced(buffer) ||
      !gst_rtcp_buffer_map(buffer, GST_MAP_READ, &rtcp))
    return GST_PAD_PROBE_OK;
  GstRTCPPacket packet;
  for (gboolean more = gst_rtcp_buffer_get_first_packet(&rtcp, &packet); more;
       more = gst_rtcp_packet_move_to_next(&packet)) {
    const GstRTCPType type = gst_rtcp_packet_get_type(&packet);
    if (type != GST_RTCP_TYPE_RR && type != GST_RTCP_TYPE_SR) continue;
    for (guint i = 0; i < gst_rtcp_packet_get_rb_count(&packet); ++i) {
      guint32 ssrc = 0, exthighestseq = 0, jitter = 0, lsr = 0, dlsr = 0;
      guint8 fractionlost = 0;
      gint32 packetslost = 0;
      gst_rtcp_packet_get_rb(&packet, i, &ssrc, &fractionlost, &packetslost, &exthighestseq,
                             &jitter, &lsr, &dlsr);
      const int64_t rtt = drivers::round_trip_from_report_block(arrival, lsr, dlsr);
      if (rtt < 0) continue;
      round_trip_ns_.store(rtt, std::memory_order_relaxed);
      round_trips_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  gst_rtcp_buffer_unmap(&rtcp);
  return GST_PAD_PROBE_OK;
}

RtpSenderStats RtpSender::stats() const {
  RtpSenderStats s;
  s.frames_pushed = pushed_.load();
  s.frames_refused = refused_.load();
  s.packets_stamped = packets_stamped_.load();
  s.frames_stamped = frames_stamped_.load();
  s.sender_reports = sender_reports_.load();
  s.round_trips = round_trips_.load();
  s.round_trip_ns = round_trip_ns_.load();
  s.packets_with_calibration = packets_calibrated_.load();
  s.frames_encoded = frames_encoded_.load();
  s.key_frames = key_frames_.load();
  s.last_key_frame_index = last_key_frame_index_.load();
  s.view_feedback_received = feedback_received_.load();
  for (std::size_t i = 0; i < s.view_feedback_malformed.size(); ++i)
    s.view_feedback_malformed[i] = feedback_malformed_[i].load();
  s.frames_skipped_not_needed = skipped_.load();
  s.key_frames_forced = forced_.load();
  s.needed = needed_reported_.load();
  if (rtxsend_ != nullptr) {
    guint requests = 0, packets = 0;
    g_object_get(rtxsend_, "num-rtx-requests", &requests, "num-rtx-packets", &packets, nullptr);
    s.rtx_requests = requests;
    s.rtx_packets_sent = packets;
  }
  return s;
}

}  // namespace hd::remote
