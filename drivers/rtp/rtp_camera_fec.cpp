// RtpCamera's ULP FEC receiver (RFC 5109 as libwebrtc and GStreamer send it: FEC packets in the
// media's SSRC and sequence numbers): rtpbin's rtpstorage keeps the packets, rtpulpfecdec behind
// the jitter buffer rebuilds one the jitter buffer gives up on. The decoder renumbers what it
// passes on (the FEC packets leave gaps the depayloader would take for losses), so the wire's
// numbers, by which the frame stamper knows each packet's arrival, are kept beside.
#include <gst/rtp/gstrtpbuffer.h>

#include <algorithm>

#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_receive_pipeline.h"

namespace hd::drivers {
namespace {

RtpCamera& camera(gpointer self) {
  return *static_cast<RtpCamera*>(self);
}

std::optional<uint16_t> sequence_of(GstBuffer* buffer) {
  GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
  if (!gst_rtp_buffer_map(buffer, GST_MAP_READ, &rtp)) return std::nullopt;
  const uint16_t s = gst_rtp_buffer_get_seq(&rtp);
  gst_rtp_buffer_unmap(&rtp);
  return s;
}

}  // namespace

void RtpCamera::wire_fec(GstElement* rtpbin) {
  if (!config_.fec) return;
  // The jitter buffer passes a payload type on only with its clock rate, and rtpbin's payload
  // demuxer, after it, drops one whose caps say is-fec: the FEC packets keep their place in the
  // sequence through the jitter buffer (a lost one is asked for like media) and go no further.
  g_signal_connect(rtpbin, "request-pt-map",
                   G_CALLBACK(+[](GstElement*, guint, guint pt, gpointer self) -> GstCaps* {
                     const RtpReceiveConfig& c = camera(self).config_;
                     if (int(pt) != c.fec_payload_type) return nullptr;
                     return gst_caps_new_simple(
                         "application/x-rtp", "media", G_TYPE_STRING, "video", "clock-rate",
                         G_TYPE_INT, 90000, "encoding-name", G_TYPE_STRING, "ULPFEC", "payload",
                         G_TYPE_INT, int(pt), "is-fec", G_TYPE_BOOLEAN, TRUE, nullptr);
                   }),
                   this);
  g_signal_connect(rtpbin, "request-fec-decoder",
                   G_CALLBACK(+[](GstElement* bin, guint session, gpointer self) -> GstElement* {
                     GstElement* dec = gst_element_factory_make("rtpulpfecdec", nullptr);
                     if (dec == nullptr) return nullptr;  // no FEC: the stream still plays
                     GObject* storage = nullptr;
                     g_signal_emit_by_name(bin, "get-internal-storage", session, &storage);
                     g_object_set(dec, "pt", guint(camera(self).config_.fec_payload_type),
                                  "storage", storage, nullptr);
                     if (storage != nullptr) g_object_unref(storage);
                     camera(self).wire_fec_decoder(dec);
                     return dec;  // floating: rtpbin adds it to itself
                   }),
                   this);
  // The storage keeps packets for as long as the jitter buffer may wait for one (its default
  // keeps none), and a frame longer.
  GstElement* storage = nullptr;
  g_signal_emit_by_name(rtpbin, "get-storage", 0u, &storage);
  if (storage == nullptr) return;
  const int keep_ms = std::max(config_.jitter_buffer_latency_ms, config_.jitter_buffer_max_ms) + 50;
  g_object_set(storage, "size-time", guint64(keep_ms) * GST_MSECOND, nullptr);
  gst_object_unref(storage);
}

// All three probes run in the jitter buffer's thread, which pushes both packets and its loss
// events through the decoder: a packet out follows the packet in or the loss it rebuilt.
void RtpCamera::wire_fec_decoder(GstElement* dec) {
  GstPad* sink = gst_element_get_static_pad(dec, "sink");
  GstPad* src = gst_element_get_static_pad(dec, "src");
  gst_pad_add_probe(
      sink, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        RtpCamera& me = camera(self);
        if (const auto s = sequence_of(GST_PAD_PROBE_INFO_BUFFER(info))) me.fec_wire_sequence_ = *s;
        me.fec_rebuilding_ = false;
        return GST_PAD_PROBE_OK;
      },
      this, nullptr);
  gst_pad_add_probe(
      sink, GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM,
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        GstEvent* e = GST_PAD_PROBE_INFO_EVENT(info);
        guint seq = 0;
        if (GST_EVENT_TYPE(e) == GST_EVENT_CUSTOM_DOWNSTREAM &&
            gst_event_has_name(e, "GstRTPPacketLost") &&
            gst_structure_get_uint(gst_event_get_structure(e), "seqnum", &seq)) {
          camera(self).fec_wire_sequence_ = static_cast<uint16_t>(seq);
          camera(self).fec_rebuilding_ = true;
        }
        return GST_PAD_PROBE_OK;
      },
      this, nullptr);
  gst_pad_add_probe(
      src, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo* info, gpointer self) {
        RtpCamera& me = camera(self);
        const auto out = sequence_of(GST_PAD_PROBE_INFO_BUFFER(info));
        if (!out) return GST_PAD_PROBE_OK;
        me.fec_sequences_[*out % me.fec_sequences_.size()].store(
            uint32_t{me.fec_wire_sequence_} << 16 | *out, std::memory_order_release);
        if (me.fec_rebuilding_) me.counters_.fec_recovered.fetch_add(1, std::memory_order_relaxed);
        me.fec_rebuilding_ = false;
        return GST_PAD_PROBE_OK;
      },
      this, nullptr);
  gst_object_unref(sink);
  gst_object_unref(src);
}

uint16_t RtpCamera::wire_sequence(uint16_t depayloader_sequence) const {
  if (!config_.fec) return depayloader_sequence;
  const uint32_t v =
      fec_sequences_[depayloader_sequence % fec_sequences_.size()].load(std::memory_order_acquire);
  // Not passed by the decoder (no FEC decoder in this pipeline): the number is the wire's.
  return (v & 0xFFFF) == depayloader_sequence ? static_cast<uint16_t>(v >> 16)
                                              : depayloader_sequence;
}

}  // namespace hd::drivers
