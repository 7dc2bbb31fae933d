// RtpCamera's side of healing after a loss (drivers/rtp/h264_heal_watch.h): every access unit out
// of the depayloader is judged, its decoded frame shown only when whole, and key frames are asked
// for here, not by rtph264depay: it counts only IDR, SPS and PPS as key, so with its
// wait-for-keyframe it would drop a refreshing stream's access units after a loss until an IDR
// that never comes, and with request-keyframe ask for one on every loss.
#include <gst/video/video.h>

#include <string_view>

#include "drivers/gobject_ptr.h"
#include "drivers/gst/gst_ptr.h"
#include "drivers/rtp/access_unit_mark.h"
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

bool RtpCamera::judge_access_unit(GstPad* pad, GstBuffer*& buffer) {
  H264AccessUnitInfo info;
  GstMapInfo map;
  if (gst_buffer_map(buffer, &map, GST_MAP_READ)) {
    info = scan_h264_access_unit(std::span<const uint8_t>(map.data, map.size), framing_of(pad));
    gst_buffer_unmap(buffer, &map);
  } else {
    info.malformed = true;  // unreadable: not known to be whole
  }
  const H264HealWatch::Verdict v = heal_.access_unit(GST_BUFFER_PTS(buffer), info);
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
  if (!v.whole && !heal_.heals_by_refresh()) {
    counters_.frames_damaged.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  // The verdict travels with the access unit to its decoded frame (access_unit_mark.h): matching
  // decoded frames to verdicts by PTS failed after a fuzzed stream, 351 frames without one.
  buffer = gst_buffer_make_writable(buffer);
  mark_access_unit(buffer, {GST_BUFFER_PTS(buffer), v.whole});
  return true;
}

}  // namespace hd::drivers
