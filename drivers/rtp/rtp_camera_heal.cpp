// RtpCamera's side of healing after a loss (drivers/rtp/h264_heal_watch.h): every access unit out
// of the depayloader is judged, its decoded frame shown only when whole, and key frames are asked
// for here, not by rtph264depay: it counts only IDR, SPS and PPS as key, so with its
// wait-for-keyframe it would drop a refreshing stream's access units after a loss until an IDR
// that never comes, and with request-keyframe ask for one on every loss.
#include <gst/video/video.h>

#include <string_view>

#include "drivers/gobject_ptr.h"
#include "drivers/gst/gst_ptr.h"
#include "drivers/rtp/rtp_camera.h"

namespace hd::drivers {
namespace {

// rtph264depay outputs avc (4-byte lengths) or byte-stream, as avdec_h264 negotiated.
H264Framing framing_of(GstPad* pad) {
  const GstCapsPtr caps(gst_pad_get_current_caps(pad));
  const GstStructure* s = caps ? gst_caps_get_structure(caps.get(), 0) : nullptr;
  const char* format = s != nullptr ? gst_structure_get_string(s, "stream-format") : nullptr;
  return format != nullptr && std::string_view(format) == "avc" ? H264Framing::kAvc
                                                                : H264Framing::kAnnexB;
}

}  // namespace

void RtpCamera::on_packet_lost() {
  counters_.jitter_lost.fetch_add(1, std::memory_order_relaxed);
  heal_.lost();
}

bool RtpCamera::judge_access_unit(GstPad* pad, GstBuffer* buffer) {
  H264AccessUnitInfo info;
  GstMapInfo map;
  if (gst_buffer_map(buffer, &map, GST_MAP_READ)) {
    info = scan_h264_access_unit(std::span<const uint8_t>(map.data, map.size), framing_of(pad));
    gst_buffer_unmap(buffer, &map);
  } else {
    info.malformed = true;  // unreadable: not known to be whole
  }
  const H264HealWatch::Verdict v = heal_.access_unit(GST_BUFFER_PTS(buffer), info);
  verdicts_[verdict_next_] = {GST_BUFFER_PTS(buffer), v.whole};
  verdict_next_ = (verdict_next_ + 1) % verdicts_.size();
  counters_.refresh_frames.store(heal_.refresh_frames(), std::memory_order_relaxed);
  if (v.request_key_frame) {  // from the depayloader's sink, as its request-keyframe did
    const GstElementPtr depay(gst_pad_get_parent_element(pad));
    const GstPadPtr sink(depay ? gst_element_get_static_pad(depay.get(), "sink") : nullptr);
    if (sink && gst_pad_push_event(sink.get(), gst_video_event_new_upstream_force_key_unit(
                                                   GST_CLOCK_TIME_NONE, TRUE, 0)))
      counters_.key_frame_requests.fetch_add(1, std::memory_order_relaxed);
  }
  // A damaged stream that heals only by IDR: nothing after the loss helps the IDR, so the access
  // unit is not decoded at all (as rtph264depay's wait-for-keyframe did). One that heals by
  // refresh needs every access unit decoded: the sweep builds on them.
  if (v.whole || heal_.heals_by_refresh()) return true;
  counters_.frames_damaged.fetch_add(1, std::memory_order_relaxed);
  return false;
}

std::optional<bool> RtpCamera::whole_picture(uint64_t pts) const {
  for (const auto& [p, whole] : verdicts_)
    if (p == pts) return whole;
  // No verdict: the access unit is older than the 16 newest (a decoder that far behind), had no
  // PTS, or the decoder put out another PTS (GstVideoDecoder holds its output PTS at the last
  // one out while its input's go backwards); not known to be whole, so not shown.
  return std::nullopt;
}

// GstVideoDecoder never lets its output PTS go back: a frame whose PTS is below the last one out
// leaves with that one's (gst_video_decoder_prepare_finish_frame). One access unit whose PTS ran
// ahead (a mutated RTP time the stream guard let through, which the jitter buffer's clock
// estimate then followed) gave every later frame one PTS for seconds, matching no verdict or
// stamp: 3.2 s without video was measured after the depayload fuzz. So the decoder is given PTS
// that only rise, and the frames it puts out are mapped back.
GstBuffer* RtpCamera::to_decoder_pts(GstBuffer* access_unit) {
  const GstClockTime pts = GST_BUFFER_PTS(access_unit);
  if (!GST_CLOCK_TIME_IS_VALID(pts)) return access_unit;
  if (pts > decoder_pts_ || decoder_pts_ == 0) {
    decoder_pts_ = pts;
    return access_unit;
  }
  ++decoder_pts_;  // a nanosecond past the newest: never below it
  moved_pts_[moved_next_] = {decoder_pts_, pts};
  moved_next_ = (moved_next_ + 1) % moved_pts_.size();
  access_unit = gst_buffer_make_writable(access_unit);
  GST_BUFFER_PTS(access_unit) = decoder_pts_;
  return access_unit;
}

uint64_t RtpCamera::from_decoder_pts(uint64_t decoder_pts) const {
  for (const auto& [moved, own] : moved_pts_)
    if (moved == decoder_pts) return own;
  return decoder_pts;
}

}  // namespace hd::drivers
