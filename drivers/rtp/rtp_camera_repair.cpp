// RtpCamera's loss repair beside rtpbin's NACK/RTX: the jitter buffer sized from the link as
// measured (jitter_budget.h) and a frame's missing last packet asked for at once
// (frame_end_requester.h). Both see each packet where it enters rtpbin, after any fault
// injection: what the jitter buffer itself gets.
#include <gst/rtp/gstrtpbuffer.h>

#include "drivers/clock/monotonic_clock.h"
#include "drivers/rtp/rtp_camera.h"
#include "drivers/rtp/rtp_receive_pipeline.h"

namespace hd::drivers {

GstBuffer* RtpCamera::on_media_into_rtpbin(GstBuffer* buffer) {
  const int64_t now = monotonic_now_ns();
  // Fault injection holds packets back but keeps udpsrc's stamps: the jitter buffer would see a
  // link without jitter whose packets come late. Stamped with their arrival here, as a real
  // link's would be by udpsrc.
  const GstClockTime base = pipeline_.base_time();
  if (config_.netsim() && GST_CLOCK_TIME_IS_VALID(base) && now > int64_t(base)) {
    buffer = gst_buffer_make_writable(buffer);
    GST_BUFFER_DTS(buffer) = GstClockTime(now) - base;
  }
  GstMapInfo map;
  if (!gst_buffer_map(buffer, &map, GST_MAP_READ)) return buffer;
  RtpPacketView view;
  const bool parsed =
      parse_rtp_packet(std::span<const uint8_t>(map.data, map.size), view) == RtpPacketError::kNone;
  uint16_t sequence = view.sequence;
  bool media = parsed && view.payload_type == config_.payload_type;
  // A repair carries the original sequence number first (RFC 4588 4), its marker bit and RTP
  // time are the original's.
  if (parsed && view.payload_type == config_.rtx_payload_type && view.payload.size() >= 2) {
    sequence = static_cast<uint16_t>(view.payload[0] << 8 | view.payload[1]);
    media = true;
  }
  gst_buffer_unmap(buffer, &map);
  if (!media) return buffer;
  if (view.payload_type == config_.payload_type)
    media_ssrc_.store(view.ssrc, std::memory_order_relaxed);
  {
    std::lock_guard lock(budget_mutex_);
    budget_.add_packet(view.timestamp, sequence, now, view.payload_type != config_.payload_type);
  }
  if (config_.retransmission && config_.frame_end_requests)  // a repair's SSRC is the RTX one
    frame_end_->on_packet(view.payload_type == config_.payload_type ? view.ssrc : 0, sequence,
                          view.marker, now);
  return buffer;
}

void RtpCamera::on_new_jitter_buffer(GstElement* jitter_buffer) {
  {
    std::lock_guard lock(budget_mutex_);
    if (jitter_buffer_ != nullptr) gst_object_unref(jitter_buffer_);
    jitter_buffer_ = GST_ELEMENT(gst_object_ref(jitter_buffer));
    budget_ = JitterBudget(budget_.settings());
  }
  latency_ms_.store(initial_latency_ms(config_), std::memory_order_relaxed);
  if (!config_.retransmission || !config_.frame_end_requests) return;
  frame_end_->set_jitter_buffer(jitter_buffer);
  // The repair of a packet asked for here is the packet to the jitter buffer, which would drop
  // a retransmission it did not ask for itself.
  GstPad* sink = gst_element_get_static_pad(jitter_buffer, "sink");
  if (sink == nullptr) return;
  gst_pad_add_probe(
      sink, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad*, GstPadProbeInfo* info, gpointer data) {
        GstBuffer* b = GST_PAD_PROBE_INFO_BUFFER(info);
        if (!GST_BUFFER_FLAG_IS_SET(b, GST_RTP_BUFFER_FLAG_RETRANSMISSION)) return GST_PAD_PROBE_OK;
        GstRTPBuffer rtp = GST_RTP_BUFFER_INIT;
        if (!gst_rtp_buffer_map(b, GST_MAP_READ, &rtp)) return GST_PAD_PROBE_OK;
        const uint16_t seq = gst_rtp_buffer_get_seq(&rtp);
        gst_rtp_buffer_unmap(&rtp);
        auto* requester = static_cast<FrameEndRequester*>(data);
        if (!requester->take_repair(seq)) return GST_PAD_PROBE_OK;
        b = gst_buffer_make_writable(b);
        GST_BUFFER_FLAG_UNSET(b, GST_RTP_BUFFER_FLAG_RETRANSMISSION);
        GST_PAD_PROBE_INFO_DATA(info) = b;
        return GST_PAD_PROBE_OK;
      },
      frame_end_.get(), nullptr);
  gst_object_unref(sink);
}

// Bus thread, every turn (<= 100 ms): the budget as measured now onto the jitter buffer. Up at
// once; down by at most 5 ms a turn, so that packets it holds are never over a latency that
// shrank under them (drop-on-latency would drop the oldest).
void RtpCamera::apply_jitter_budget() {
  GstElement* jb = nullptr;
  int want = 0, rtt_ms = 0;
  int64_t wait_ns = 0, frame_end_wait_ns = 0, burst_gap_ns = 0;
  {
    std::lock_guard lock(budget_mutex_);
    if (jitter_buffer_ == nullptr) return;
    jb = GST_ELEMENT(gst_object_ref(jitter_buffer_));
    GstStructure* st = nullptr;
    g_object_get(jb, "stats", &st, nullptr);
    guint64 rtt = 0;
    if (st != nullptr && gst_structure_get_uint64(st, "rtx-rtt", &rtt)) {
      budget_.set_round_trip(static_cast<int64_t>(rtt));
      rtt_ms = static_cast<int>(rtt / 1'000'000);
    }
    if (st != nullptr) gst_structure_free(st);
    want = config_.jitter_buffer_auto ? budget_.latency_ms() : config_.jitter_buffer_latency_ms;
    wait_ns = budget_.request_wait_ns();
    frame_end_wait_ns = budget_.frame_end_wait_ns();
    burst_gap_ns = budget_.burst_gap_ns();
  }
  const int now_ms = latency_ms_.load(std::memory_order_relaxed);
  const int next = want >= now_ms ? want : std::max(want, now_ms - 5);
  if (next != now_ms) {
    g_object_set(jb, "latency", static_cast<guint>(next), nullptr);
    latency_ms_.store(next, std::memory_order_relaxed);
  }
  frame_end_->set_deadline(next, rtt_ms);
  if (config_.retransmission && config_.jitter_buffer_auto) {
    // A gap shorter than the link's reorder is a packet on its way: asked for only after it
    // (a request at once on reordering, as on a LAN, only while the link does not reorder).
    // The jitter buffer expects a missing packet between its neighbours' arrivals, which are
    // themselves up to the reorder early: 1.5 x reorder past that before asking.
    const int wait_ms = static_cast<int>((wait_ns * 3 / 2 + 999'999) / 1'000'000);
    const bool reorders = wait_ns > int64_t{config_.rtx_delay_ms} * 3'000'000;
    // A repair that did not come is asked for again after the round trip (rtx-rtt: the
    // jitter buffer's mean, the link's jitter in it), half the link's longest burst pause and
    // the wait; asking before the repair could have come only brings duplicates (a 7 ms retry
    // asked 5 times per loss on a 50 ms jitter link: +22 % bytes). Retries go on until the
    // packet's deadline (rtx-retry-period, else GStreamer derives it from the latency minus
    // one retry and gives a repair up early: measured, a 110 ms retry made it pts + 100 ms
    // with a 188 ms latency).
    const int retry_ms =
        wait_ms + std::max(2, rtt_ms) + 2 + static_cast<int>(burst_gap_ns / 2 / 1'000'000);
    g_object_set(jb, "rtx-delay", reorders ? wait_ms : config_.rtx_delay_ms, "rtx-delay-reorder",
                 reorders ? 0 : config_.rtx_delay_reorder, "rtx-retry-timeout", retry_ms,
                 "rtx-min-retry-timeout", retry_ms, "rtx-retry-period", next, nullptr);
    frame_end_->set_wait(frame_end_wait_ns);
  }
  gst_object_unref(jb);
}

}  // namespace hd::drivers
