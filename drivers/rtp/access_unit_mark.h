#pragma once
// An access unit's mark: its own PTS and its heal verdict, carried as a custom GstMeta on the
// buffer through avdec_h264 and videoconvert to its decoded frame. GstVideoDecoder and
// videoconvert copy a meta without tags, so a decoded frame finds its access unit whatever PTS the
// decoder gave it (GstVideoDecoder replaces PTS it finds out of order, and libav may hold frames
// back after a damaged stream) and however many frames the decoder holds.

#include <gst/gst.h>

#include <cstdint>
#include <optional>

namespace hd::drivers {

struct AccessUnitMark {
  uint64_t pts = 0;    ///< its PTS out of the depayloader: the frame stamper's key
  bool whole = false;  ///< H264HealWatch's verdict: its picture may be shown
};

/// Marks a writable buffer (replacing a mark it had).
void mark_access_unit(GstBuffer* buffer, const AccessUnitMark& mark);
/// The mark a buffer carries; nullopt when it has none (a frame the decoder made up).
std::optional<AccessUnitMark> access_unit_mark(GstBuffer* buffer);

}  // namespace hd::drivers
