#pragma once
// The run's per-frame decisions, kept in storage sized (and touched) before the loop starts, so
// a long run's memory stays flat and the render thread never allocates to log.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "station/frame/station_frame.h"

namespace hd::station {

/// One frame as frames.csv and trace.png show it.
struct FrameLogRow {
  station::FrameRow decision;  ///< m, w_video, camera, variant, guidance, head position
  double t_s = 0.0;            ///< slot start since the first frame's slot start
  bool missed_deadline = false;
};

/// Keeps the first `capacity` rows; later ones are counted in dropped().
class FrameLog {
 public:
  explicit FrameLog(std::size_t capacity);
  void add(const FrameLogRow& row) {
    if (size_ < rows_.size())
      rows_[size_++] = row;
    else
      ++dropped_;
  }
  std::size_t size() const { return size_; }
  uint64_t dropped() const { return dropped_; }
  const FrameLogRow& operator[](std::size_t i) const { return rows_[i]; }
  const FrameLogRow* begin() const { return rows_.data(); }
  const FrameLogRow* end() const { return rows_.data() + size_; }

 private:
  std::vector<FrameLogRow> rows_;
  std::size_t size_ = 0;
  uint64_t dropped_ = 0;
};

}  // namespace hd::station
