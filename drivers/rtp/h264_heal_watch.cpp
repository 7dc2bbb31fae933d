// H264HealWatch: broken access units from sequence gaps and lost events, and the damaged state
// an IDR or a recovery point (after its recovery_frame_cnt frames) ends.
#include "drivers/rtp/h264_heal_watch.h"

#include <algorithm>

namespace hd::drivers {

void H264HealWatch::mark_broken(uint64_t pts) {
  if (broken(pts)) return;
  broken_[broken_next_] = pts;
  broken_next_ = (broken_next_ + 1) % broken_.size();
  broken_count_ = std::min(broken_count_ + 1, broken_.size());
}

bool H264HealWatch::broken(uint64_t pts) const {
  return std::find(broken_.begin(), broken_.begin() + broken_count_, pts) !=
         broken_.begin() + broken_count_;
}

void H264HealWatch::packet(uint16_t sequence, uint64_t pts, bool marker, bool starts_picture) {
  if (have_packet_ && sequence != uint16_t(last_sequence_ + 1)) {
    // The missing packets were the previous access unit's tail (unless it had ended), this one's
    // head (unless this packet begins it), or whole access units between. Every access unit
    // judged from here on comes after them.
    damaged_ = true;
    countdown_ = -1;
    requested_ = false;  // a new loss: ask again
    if (!last_marker_) mark_broken(last_pts_);
    if (pts == last_pts_ || !starts_picture) mark_broken(pts);
  }
  have_packet_ = true;
  last_sequence_ = sequence;
  last_pts_ = pts;
  last_marker_ = marker;
}

void H264HealWatch::lost() {
  damaged_ = true;
  countdown_ = -1;
  requested_ = false;
  if (have_packet_ && !last_marker_) mark_broken(last_pts_);
}

H264HealWatch::Verdict H264HealWatch::access_unit(uint64_t pts, const H264AccessUnitInfo& info) {
  Verdict v;
  const bool intact = !broken(pts) && !info.malformed;
  // Only an intact access unit's recovery point says how the sender heals: a damaged one (a
  // fuzzed stream's) would switch a stream that heals by IDR off its key-frame requests.
  if (intact && info.recovery_frame_cnt && !info.idr)
    refresh_frames_ = static_cast<int>(std::min<uint32_t>(*info.recovery_frame_cnt, 65535) + 1);
  if (!intact) {
    damaged_ = true;
    countdown_ = -1;
  } else if (info.idr) {
    damaged_ = false;
    countdown_ = -1;
  } else if (damaged_ && countdown_ > 0) {
    --countdown_;
  } else if (damaged_ && info.recovery_frame_cnt) {
    countdown_ = *info.recovery_frame_cnt;
  }
  if (damaged_ && countdown_ == 0) {
    damaged_ = false;
    countdown_ = -1;
  }
  v.whole = !damaged_;
  if (!damaged_) {
    requested_ = false;
    return v;
  }
  if (!heals_by_refresh() && !requested_) {
    v.request_key_frame = true;
    requested_ = true;
  }
  return v;
}

}  // namespace hd::drivers
