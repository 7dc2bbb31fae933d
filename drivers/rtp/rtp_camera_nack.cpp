// RtpCamera's immediate feedback: every retransmission request (the jitter buffer's, and the
// frame-end watch's) and every key-frame request (the depayloader's, after a packet was given up
// on) leaves at once as its own compound RTCP packet (an empty receiver report and a Generic NACK,
// RFC 4585 6.2.1, or a PLI, 6.3.1), from the RTCP socket to where feedback goes.
//
// Why: rtpsession sends a NACK with its next RTCP, early at most once per regular interval (RFC
// 4585 3.5.2), and that interval follows the RTCP bandwidth: 50-80 ms here (measured from its
// debug log at 20 000 B/s), up to twice that before a NACK left (124 ms seen), past any deadline a
// small jitter buffer has. A station and one sender are a point-to-point session, where RFC
// 4585's immediate feedback mode is meant to send each feedback at once; ~40 bytes each. The
// request still passes rtprtxreceive (which notes it to match the repair), then stops before
// rtpsession, which would ask a second time. With SRTP the request goes through rtpsession as
// before (the sender takes only SRTCP, which this does not make).
//
// Bounded: at most kBurst NACKs at once and kPerSecond on average (a 3 s cut's return asked for
// 5671 packets, one datagram each); beyond, requests go through rtpsession, which batches and
// expires them. One PLI per kPliIntervalNs: the key frame asked for is on its way, more would
// only make more.
#include <gio/gio.h>
#include <gst/rtp/gstrtcpbuffer.h>
#include <gst/video/video.h>

#include <algorithm>

#include "drivers/clock/monotonic_clock.h"

#include "drivers/gobject_ptr.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_receive_pipeline.h"

namespace hd::drivers {
namespace {

bool is_retransmission_request(GstEvent* e) {
  return GST_EVENT_TYPE(e) == GST_EVENT_CUSTOM_UPSTREAM &&
         gst_event_has_name(e, "GstRTPRetransmissionRequest");
}

bool is_key_frame_request(GstEvent* e) {
  return GST_EVENT_TYPE(e) == GST_EVENT_CUSTOM_UPSTREAM && gst_video_event_is_force_key_unit(e);
}

constexpr double kBurst = 64.0;
constexpr double kPerSecond = 400.0;  // a 4 Mbit/s stream's packets: every one of them lost
constexpr int64_t kPliIntervalNs = 100'000'000;

}  // namespace

bool RtpCamera::feedback_allowed(bool pli) {
  std::lock_guard lock(feedback_mutex_);
  const int64_t now = monotonic_now_ns();
  if (pli) {
    if (last_pli_ns_ != 0 && now - last_pli_ns_ < kPliIntervalNs) return false;
    last_pli_ns_ = now;
    return true;
  }
  nack_tokens_ = std::min(kBurst, nack_tokens_ + double(now - nack_tokens_ns_) * 1e-9 * kPerSecond);
  nack_tokens_ns_ = now;
  if (nack_tokens_ < 1.0) return false;
  nack_tokens_ -= 1.0;
  return true;
}

bool RtpCamera::send_feedback(uint32_t media_ssrc, std::optional<uint16_t> nack_sequence) {
  std::string host;
  int port = 0;
  GstElementPtr src;
  GObjectPtr<GObject> session;
  {
    std::lock_guard lock(feedback_mutex_);
    const std::size_t colon = feedback_to_.rfind(':');
    if (colon == std::string::npos) return false;  // no sender heard yet
    host = feedback_to_.substr(0, colon);
    port = std::stoi(feedback_to_.substr(colon + 1));
    if (!feedback_source_ || !feedback_session_) return false;
    src.reset(GST_ELEMENT(gst_object_ref(feedback_source_.get())));
    session.reset(G_OBJECT(g_object_ref(feedback_session_.get())));
  }
  guint own_ssrc = 0;
  g_object_get(session.get(), "internal-ssrc", &own_ssrc, nullptr);
  GstBuffer* buffer = gst_rtcp_buffer_new(128);
  GstRTCPBuffer rtcp = GST_RTCP_BUFFER_INIT;
  gst_rtcp_buffer_map(buffer, GST_MAP_READWRITE, &rtcp);
  GstRTCPPacket packet;
  bool ok = gst_rtcp_buffer_add_packet(&rtcp, GST_RTCP_TYPE_RR, &packet);
  if (ok) gst_rtcp_packet_rr_set_ssrc(&packet, own_ssrc);
  ok = ok && gst_rtcp_buffer_add_packet(
                 &rtcp, nack_sequence ? GST_RTCP_TYPE_RTPFB : GST_RTCP_TYPE_PSFB, &packet);
  if (ok) {
    gst_rtcp_packet_fb_set_type(&packet,
                                nack_sequence ? GST_RTCP_RTPFB_TYPE_NACK : GST_RTCP_PSFB_TYPE_PLI);
    gst_rtcp_packet_fb_set_sender_ssrc(&packet, own_ssrc);
    gst_rtcp_packet_fb_set_media_ssrc(&packet, media_ssrc);
  }
  if (ok && nack_sequence) {
    ok = gst_rtcp_packet_fb_set_fci_length(&packet, 1);
    guint8* fci = ok ? gst_rtcp_packet_fb_get_fci(&packet) : nullptr;
    if (fci != nullptr) {
      fci[0] = static_cast<guint8>(*nack_sequence >> 8);  // PID
      fci[1] = static_cast<guint8>(*nack_sequence & 0xFF);
      fci[2] = fci[3] = 0;  // BLP: only this one
    }
  }
  gst_rtcp_buffer_unmap(&rtcp);
  GstMapInfo map;
  bool sent = false;
  if (ok && gst_buffer_map(buffer, &map, GST_MAP_READ)) {
    GSocket* socket_out = nullptr;
    g_object_get(src.get(), "used-socket", &socket_out, nullptr);
    const GObjectPtr<GSocket> socket(socket_out);
    const GObjectPtr<GSocketAddress> to(g_inet_socket_address_new_from_string(host.c_str(), port));
    sent = socket && to &&
           g_socket_send_to(socket.get(), to.get(), reinterpret_cast<const gchar*>(map.data),
                            map.size, nullptr, nullptr) == gssize(map.size);
    gst_buffer_unmap(buffer, &map);
  }
  gst_buffer_unref(buffer);
  if (sent)
    (nack_sequence ? counters_.nacks_sent_at_once : counters_.plis_sent_at_once)
        .fetch_add(1, std::memory_order_relaxed);
  return sent;
}

void RtpCamera::wire_immediate_nack(GstElement* rtx_receive) {
  if (config_.srtp_key) return;
  GstPad* src = gst_element_get_static_pad(rtx_receive, "src");
  GstPad* sink = gst_element_get_static_pad(rtx_receive, "sink");
  if (src == nullptr || sink == nullptr) {
    if (src != nullptr) gst_object_unref(src);
    if (sink != nullptr) gst_object_unref(sink);
    return;
  }
  // Into rtprtxreceive: sent now, and marked as sent on the event.
  gst_pad_add_probe(
      src, GST_PAD_PROBE_TYPE_EVENT_UPSTREAM,
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        auto& camera = *static_cast<RtpCamera*>(self);
        GstEvent* e = GST_PAD_PROBE_INFO_EVENT(info);
        bool sent = false;
        if (is_retransmission_request(e)) {
          const GstStructure* s = gst_event_get_structure(e);
          guint seq = 0, ssrc = 0;
          if (gst_structure_get_uint(s, "seqnum", &seq) &&
              gst_structure_get_uint(s, "ssrc", &ssrc) && camera.feedback_allowed(false))
            sent = camera.send_feedback(ssrc, static_cast<uint16_t>(seq));
        } else if (is_key_frame_request(e)) {
          const uint32_t ssrc = camera.media_ssrc_.load(std::memory_order_relaxed);
          if (ssrc == 0) return GST_PAD_PROBE_OK;  // no stream yet: rtpsession's
          if (!camera.feedback_allowed(true)) return GST_PAD_PROBE_DROP;  // one is on its way
          sent = camera.send_feedback(ssrc, std::nullopt);
        } else {
          return GST_PAD_PROBE_OK;
        }
        if (sent) {
          e = GST_EVENT(gst_mini_object_make_writable(GST_MINI_OBJECT(e)));
          gst_structure_set(gst_event_writable_structure(e), "hd-sent", G_TYPE_BOOLEAN, TRUE,
                            nullptr);
          GST_PAD_PROBE_INFO_DATA(info) = e;
        }
        return GST_PAD_PROBE_OK;
      },
      this, nullptr);
  // Out of it towards rtpsession: a request already sent stops here.
  gst_pad_add_probe(
      sink, GST_PAD_PROBE_TYPE_EVENT_UPSTREAM,
      [](GstPad*, GstPadProbeInfo* info, gpointer) {
        GstEvent* e = GST_PAD_PROBE_INFO_EVENT(info);
        gboolean sent = FALSE;
        if ((is_retransmission_request(e) || is_key_frame_request(e)) &&
            gst_event_get_structure(e) != nullptr &&
            gst_structure_get_boolean(gst_event_get_structure(e), "hd-sent", &sent) && sent)
          return GST_PAD_PROBE_DROP;
        return GST_PAD_PROBE_OK;
      },
      nullptr, nullptr);
  gst_object_unref(src);
  gst_object_unref(sink);
}

}  // namespace hd::drivers
