#pragma once
// Which decoded H.264 frames are whole pictures after a loss: the station's rule for a stream
// that heals by a key frame (IDR) or by intra refresh (a recovery point SEI), detected from the
// stream itself, so the station needs no setting that must match the sender's.

#include <array>
#include <cstdint>

#include "drivers/rtp/h264_recovery_point.h"

namespace hd::drivers {

/// Fed, in the depayloader's thread, with the RTP packets going into rtph264depay, its lost-packet
/// events and the access units coming out of it (pts: the GStreamer PTS, the same on a packet
/// and on the access unit made of it). An access unit is broken when a packet of it may be
/// missing: a sequence gap inside it or before it (unless its first packet after the gap begins
/// a picture: h264_payload_starts_picture), or a lost packet while it was incomplete. From a gap
/// or a broken access unit on, the stream is damaged (every picture predicted from what is
/// missing is) until
/// - an intact IDR (the picture is whole at once), or
/// - an intact access unit with a recovery point SEI, recovery_frame_cnt intact access units
///   later (H.264 D.2.8: from there on the pictures are whole). The SEI's access unit began
///   after the loss: it is intact, so no packet of it was lost. A new loss meanwhile starts
///   over.
/// Before the first IDR or recovery point the stream is damaged too (nothing to predict from).
class H264HealWatch {
 public:
  void packet(uint16_t sequence, uint64_t pts, bool marker, bool starts_picture);
  /// A GstRTPPacketLost event: the stream is damaged now; the access unit in progress (its last
  /// packet did not come) is broken.
  void lost();

  struct Verdict {
    bool whole = false;  ///< the decoded picture of this access unit is whole: may be shown
    /// Ask for a key frame (PLI): a stream that heals only by IDR is damaged, and this access
    /// unit is its first damaged one or a new loss (as rtph264depay's request-keyframe asked on
    /// every discontinuity). Never for a stream that heals by refresh: x264enc answers a
    /// force-key-unit with intra refresh on by starting another sweep (x264_encoder_intra_refresh,
    /// gstx264enc.c), not an IDR, and its sweeps are continuous anyway, so a PLI would heal
    /// nothing sooner.
    bool request_key_frame = false;
  };
  Verdict access_unit(uint64_t pts, const H264AccessUnitInfo& info);

  /// A recovery point SEI was seen outside an IDR: the sender heals by intra refresh.
  bool heals_by_refresh() const { return refresh_frames_ > 0; }
  int refresh_frames() const { return refresh_frames_; }  ///< recovery_frame_cnt + 1; 0 none

 private:
  void mark_broken(uint64_t pts);
  bool broken(uint64_t pts) const;

  bool have_packet_ = false, last_marker_ = true;
  uint16_t last_sequence_ = 0;
  uint64_t last_pts_ = 0;
  // The newest broken access units' PTS: an access unit leaves the depayloader at the latest
  // when the next one's first packet came, so a few suffice.
  std::array<uint64_t, 8> broken_{};
  std::size_t broken_next_ = 0, broken_count_ = 0;
  bool damaged_ = true;
  int64_t countdown_ = -1;  ///< intact access units until whole; -1: no recovery point pending
  int refresh_frames_ = 0;
  bool requested_ = false;  ///< a key frame was asked for since the last loss
};

}  // namespace hd::drivers
