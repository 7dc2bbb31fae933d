// RtpCamera's RTCP side: the sender's reports coming in (clock samples, where feedback goes),
// the feedback this station sends (receiver reports, NACK and PLI through rtpbin; the view
// feedback from the RTCP socket) and what rtpbin's session counted of it.
#include <gio/gio.h>
#include <gst/net/gstnetaddressmeta.h>
#include <gst/rtp/gstrtcpbuffer.h>
#include <gst/video/video.h>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/gobject_ptr.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_receive_pipeline.h"

namespace hd::drivers {

// The RTCP source's output: RTCP feedback (receiver reports, NACK, PLI) and the view feedback go
// back to where the sender's RTCP comes from.
void RtpCamera::on_rtcp_from_sender(GstBuffer* buffer) {
  set_feedback_target(buffer, true);
}

// Where feedback goes: the sender's RTCP source, or until its first report, the source of its
// first accepted RTP packet (hybrid-remote sends both from one socket, RFC 4961; to a plain
// sender's RTP port it is lost until its RTCP comes). Either thread: a mutex.
void RtpCamera::set_feedback_target(GstBuffer* buffer, bool from_rtcp) {
  if (!from_rtcp && feedback_known_.load(std::memory_order_acquire)) return;  // per packet: cheap
  GstNetAddressMeta* meta = gst_buffer_get_net_address_meta(buffer);
  if (meta == nullptr || !G_IS_INET_SOCKET_ADDRESS(meta->addr)) return;
  GInetSocketAddress* a = G_INET_SOCKET_ADDRESS(meta->addr);
  const GCharPtr host(g_inet_address_to_string(g_inet_socket_address_get_address(a)));
  const int port = g_inet_socket_address_get_port(a);
  const std::string where = std::string(host.get()) + ":" + std::to_string(port);
  {
    std::lock_guard lock(feedback_mutex_);
    if (where == feedback_to_ || (!from_rtcp && !feedback_to_.empty())) return;
    feedback_to_ = where;  // a new sender (or the first): feedback goes there now
    feedback_known_.store(true, std::memory_order_release);
  }
  if (const GstElementPtr sink = pipeline_.find(rtp_elements::kRtcpSink)) {
    g_signal_emit_by_name(sink.get(), "clear");
    g_signal_emit_by_name(sink.get(), "add", host.get(), port);
  }
  counters_.feedback_targets.fetch_add(1, std::memory_order_relaxed);
  view_.set_target(host.get(), port);
}

// RTCP into rtpbin (after srtpdec): each sender report is a sample of the sender's clock against
// its arrival here (udpsrc's arrival stamp on the pipeline clock, CLOCK_MONOTONIC).
void RtpCamera::on_rtcp_into_rtpbin(GstBuffer* buffer) {
  const int64_t now = monotonic_now_ns();
  int64_t arrival = now;
  const GstClockTime pts = GST_BUFFER_PTS(buffer);
  const GstClockTime base = pipeline_.base_time();
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
    counters_.sender_reports.fetch_add(1, std::memory_order_relaxed);
    stamper_.add_sender_report(*sent, arrival);
  }
  gst_rtcp_buffer_unmap(&rtcp);
}

RtpCamera::Feedback RtpCamera::feedback() const {
  Feedback f;
  f.key_frame_requests = counters_.key_frame_requests.load(std::memory_order_relaxed);
  f.view_feedback_sent = view_.sent();
  f.nack_sent = counters_.nacks_sent_at_once.load(std::memory_order_relaxed);
  f.pli_sent = counters_.plis_sent_at_once.load(std::memory_order_relaxed);
  if (const GstElementPtr rtx = pipeline_.find(rtp_elements::kRtxReceive)) {
    guint requests = 0, packets = 0;
    g_object_get(rtx.get(), "num-rtx-requests", &requests, "num-rtx-packets", &packets, nullptr);
    f.rtx_requested = requests;
    f.rtx_received = packets;
  }
  const GstElementPtr rtpbin = pipeline_.find(rtp_elements::kRtpBin);
  if (!rtpbin) return f;
  GObject* session_out = nullptr;
  g_signal_emit_by_name(rtpbin.get(), "get-internal-session", 0u, &session_out);
  const GObjectPtr<GObject> session(session_out);
  if (!session) return f;
  GstStructure* stats_out = nullptr;
  g_object_get(session.get(), "stats", &stats_out, nullptr);
  const GstStructurePtr stats(stats_out);
  if (!stats) return f;
  const GValue* sources = gst_structure_get_value(stats.get(), "source-stats");
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
  return f;
}

void RtpCamera::set_view_needed(bool needed) {
  view_.set_needed(needed);
}

// Bus thread: the pipeline (and its RTCP socket) is stable here.
void RtpCamera::send_view_feedback() {
  const int64_t now = monotonic_now_ns();
  if (!view_.due(now)) return;
  const GstElementPtr src = pipeline_.find(rtp_elements::kRtcpSource);
  if (!src) return;
  GSocket* socket_out = nullptr;
  g_object_get(src.get(), "used-socket", &socket_out, nullptr);
  const GObjectPtr<GSocket> socket(socket_out);
  if (!socket) return;
  // With the stream's key the message carries a tag, so that nobody else can lower a camera.
  const ViewFeedbackSchedule::Message m = view_.take(now);
  const GObjectPtr<GSocketAddress> to(
      g_inet_socket_address_new_from_string(m.host.c_str(), m.port));
  if (to && g_socket_send_to(socket.get(), to.get(), reinterpret_cast<const gchar*>(m.bytes.data()),
                             m.size, nullptr, nullptr) == gssize(m.size))
    view_.count_sent();
}

bool RtpCamera::request_key_frame() {
  const GstElementPtr depay = pipeline_.find(rtp_elements::kDepayloader);
  if (!depay) return false;
  const GstPadPtr pad(gst_element_get_static_pad(depay.get(), "sink"));
  const gboolean sent =
      pad && gst_pad_push_event(pad.get(), gst_video_event_new_upstream_force_key_unit(
                                               GST_CLOCK_TIME_NONE, TRUE, 0));
  if (sent) counters_.key_frame_requests.fetch_add(1, std::memory_order_relaxed);
  return sent;
}

}  // namespace hd::drivers
