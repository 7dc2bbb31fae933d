// RtpCamera::wire: what the camera adds to the parsed receive pipeline before it plays (RTX, the
// SRTP keys, RTCP settings, the link to rtpbin) and the probes through which it sees packets and
// frames. Every element is looked up checked: a missing one is a DeviceError naming it.
#include <gst/app/gstappsink.h>

#include "drivers/gobject_ptr.h"
#include "drivers/rtp/rtp_aux_bin.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_receive_pipeline.h"
#include "drivers/rtp/srtp_elements.h"

namespace hd::drivers {
namespace {

RtpCamera& camera(gpointer self) {
  return *static_cast<RtpCamera*>(self);
}

// rtpjitterbuffer's "drop-msg" (post-drop-messages): the packets it dropped since its last one,
// by reason (GStreamer 1.22: too late, which includes already declared lost, and over its
// latency; later versions count already lost apart). Counted and taken off the bus.
GstBusSyncReply count_jitter_drops(GstBus*, GstMessage* m, gpointer data) {
  const GstStructure* s =
      GST_MESSAGE_TYPE(m) == GST_MESSAGE_ELEMENT ? gst_message_get_structure(m) : nullptr;
  if (s == nullptr || !gst_structure_has_name(s, "drop-msg")) return GST_BUS_PASS;
  auto field = [s](const char* name) {
    guint n = 0;
    return gst_structure_get_uint(s, name, &n) ? uint64_t{n} : uint64_t{0};
  };
  RtpCameraCounters& c = *static_cast<RtpCameraCounters*>(data);
  c.jitter_too_late.fetch_add(field("num-too-late") + field("num-already-lost"),
                              std::memory_order_relaxed);
  c.jitter_over_latency.fetch_add(field("num-drop-on-latency"), std::memory_order_relaxed);
  return GST_BUS_DROP;
}

}  // namespace

void RtpCamera::wire(PipelineRunner& p) {
  heal_ = H264HealWatch{};  // a new pipeline's stream starts unhealed (no streaming thread yet)
  const GstElementPtr rtpbin = p.element(rtp_elements::kRtpBin);
  {                              // a new pipeline's multiudpsink has no destination yet
    GObject* session = nullptr;  // session 0 exists: the RTCP pads created it
    g_signal_emit_by_name(rtpbin.get(), "get-internal-session", 0u, &session);
    std::lock_guard lock(feedback_mutex_);
    feedback_to_.clear();
    feedback_known_.store(false, std::memory_order_release);
    feedback_source_ = p.element(rtp_elements::kRtcpSource);
    feedback_session_.reset(session);
  }
  g_signal_connect(rtpbin.get(), "new-jitterbuffer",
                   G_CALLBACK(+[](GstElement*, GstElement* jb, guint, guint, gpointer self) {
                     // Every packet it drops is a message (count_jitter_drops), one each: a
                     // longer interval would sum them, and the last sum would wait for a drop.
                     g_object_set(jb, "post-drop-messages", TRUE, "drop-messages-interval", 0u,
                                  nullptr);
                     camera(self).on_new_jitter_buffer(jb);
                     const RtpReceiveConfig& c = camera(self).config_;
                     if (!c.retransmission) return;
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
  {  // in the posting thread (udpsrc's): the bus thread takes only errors off the bus
    const GstBusPtr bus(gst_element_get_bus(p.raw()));
    gst_bus_set_sync_handler(bus.get(), count_jitter_drops, &counters_, nullptr);
  }
  if (config_.retransmission) {
    // RTX: answer rtpbin's request for an aux receiver, then request the pad that asks for it.
    g_signal_connect(rtpbin.get(), "request-aux-receiver",
                     G_CALLBACK(+[](GstElement*, guint session, gpointer self) {
                       return make_rtp_aux_bin(rtx_receive_description(camera(self).config_),
                                               session);
                     }),
                     this);
  }
  {
    GstElement* session_out = nullptr;  // session 0 exists: the RTCP pads created it
    g_signal_emit_by_name(rtpbin.get(), "get-session", 0u, &session_out);
    const GstElementPtr session(session_out);
    if (session)
      g_object_set(session.get(), "rtcp-fraction",
                   static_cast<gdouble>(config_.rtcp_bandwidth_bytes_per_s), nullptr);
  }
  wire_fec(rtpbin.get());
  const MediaLink from = receive_media_link(config_);
  const GstElementPtr last = p.element(from.element);
  const gboolean linked =
      gst_element_link_pads(last.get(), from.pad, rtpbin.get(), "recv_rtp_sink_0");
  // The pipeline keeps the RTX receiver; feedback() looks it up by name.
  const GstElementPtr rtx_receive = p.find(rtp_elements::kRtxReceive);
  const bool rtx_ok = !config_.retransmission || rtx_receive != nullptr;
  if (rtx_receive) wire_immediate_nack(rtx_receive.get());
  if (!linked || !rtx_ok) {
    throw DeviceError("camera " + id() + ": cannot link the receive pipeline to rtpbin" +
                      (config_.retransmission ? " (with its RTX aux receiver)" : ""));
  }

  p.probe(
      rtp_elements::kRtpBin, "recv_rtp_sink_0",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        GST_PAD_PROBE_INFO_DATA(info) =
            camera(self).on_media_into_rtpbin(GST_PAD_PROBE_INFO_BUFFER(info));
        return GST_PAD_PROBE_OK;
      },
      this);
  p.probe(
      rtp_elements::kRtpSource, "src",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        return camera(self).on_rtp_packet(GST_PAD_PROBE_INFO_BUFFER(info));
      },
      this);

  if (config_.srtp_key) {
    answer_srtp_key_requests(p.element(rtp_elements::kSrtpDecoder).get(), *config_.srtp_key);
    // The station's own RTCP (receiver reports, NACK, PLI, which ask the sender for work) is
    // SRTCP too: the sender takes only what this key protects.
    set_srtp_encoder_key(p.element(rtp_elements::kSrtpEncoder).get(), *config_.srtp_key);
    p.probe(
        rtp_elements::kSrtpDecoder, "rtp_src",
        [](GstPad*, GstPadProbeInfo* info, gpointer self) {
          return camera(self).on_decrypted(GST_PAD_PROBE_INFO_BUFFER(info));
        },
        this);
  }

  {  // receiver reports often (each gives the sender a round trip)
    GObject* session_out = nullptr;
    g_signal_emit_by_name(rtpbin.get(), "get-internal-session", 0u, &session_out);
    const GObjectPtr<GObject> session(session_out);
    if (session)
      g_object_set(session.get(), "rtcp-min-interval",
                   static_cast<guint64>(config_.rtcp_interval_ms) * GST_MSECOND, nullptr);
  }
  // The sender reports going in, after srtpdec: readable here.
  p.probe(
      rtp_elements::kRtpBin, "recv_rtcp_sink_0",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        camera(self).on_rtcp_into_rtpbin(GST_PAD_PROBE_INFO_BUFFER(info));
        return GST_PAD_PROBE_OK;
      },
      this);
  p.probe(
      rtp_elements::kDecoder, "src",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        camera(self).on_decoded(GST_PAD_PROBE_INFO_BUFFER(info));
        return GST_PAD_PROBE_OK;
      },
      this);
  p.probe(
      rtp_elements::kDepayloader, "sink",
      [](GstPad* pad, GstPadProbeInfo* info, gpointer self) {
        GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
        camera(self).on_depay_packet(pad, buffer);
        GST_PAD_PROBE_INFO_DATA(info) = buffer;  // its PTS may have been made the access unit's
        return GST_PAD_PROBE_OK;
      },
      this);
  p.probe(  // the packets the jitter buffer gave up on (do-lost): counted, the stream damaged
      rtp_elements::kDepayloader, "sink",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        const GstEvent* e = GST_PAD_PROBE_INFO_EVENT(info);
        if (GST_EVENT_TYPE(e) == GST_EVENT_CUSTOM_DOWNSTREAM &&
            gst_event_has_name(const_cast<GstEvent*>(e), "GstRTPPacketLost"))
          camera(self).on_packet_lost();
        return GST_PAD_PROBE_OK;
      },
      this, GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM);
  p.probe(
      rtp_elements::kDepayloader, "src",
      [](GstPad* pad, GstPadProbeInfo* info, gpointer self) {
        GstBuffer* buffer = GST_PAD_PROBE_INFO_BUFFER(info);
        const bool pass = camera(self).on_access_unit(pad, buffer);
        GST_PAD_PROBE_INFO_DATA(info) = buffer;
        return pass ? GST_PAD_PROBE_OK : GST_PAD_PROBE_DROP;
      },
      this);
  p.probe(
      rtp_elements::kRtcpSource, "src",
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        camera(self).on_rtcp_from_sender(GST_PAD_PROBE_INFO_BUFFER(info));
        return GST_PAD_PROBE_OK;
      },
      this);

  GstAppSinkCallbacks callbacks{};
  callbacks.new_sample = [](GstAppSink* s, gpointer self) {
    camera(self).on_sample(GST_ELEMENT(s));
    return GST_FLOW_OK;
  };
  gst_app_sink_set_callbacks(GST_APP_SINK(p.element(rtp_elements::kAppSink).get()), &callbacks,
                             this, nullptr);
}

}  // namespace hd::drivers
