#pragma once
// A line on stdout every few seconds of a long run (the soak is an hour): frames, missed
// deadlines, frames per variant, resident memory. Fed between frames, outside the counted tick,
// by plain counters: nothing is sorted or scanned per line.

#include <cstdint>
#include <cstdio>

#include "core/transition.h"

namespace hd::station {

class RunProgress {
 public:
  /// Prints every `period_s` seconds (0: never) to `out`.
  RunProgress(double period_s, std::FILE* out, int64_t start_ns);

  /// After each frame: its variant, and the loop's totals so far.
  void frame_done(core::Variant variant, uint64_t frames, uint64_t missed, int64_t now_ns);

  /// The model updater's totals so far (a run with one): each line then ends with them.
  void model_done(uint64_t updates, uint64_t reconstructions) {
    model_updates_ = updates;
    reconstructions_ = reconstructions;
    have_model_ = true;
  }

  /// The process's resident memory in KiB (/proc/self/statm), or -1 where it cannot be read.
  static long resident_kib();

 private:
  int64_t period_ns_;
  std::FILE* out_;
  int64_t start_ns_, next_ns_;
  uint64_t variants_[3] = {0, 0, 0};  ///< video, hybrid, synthetic
  bool have_model_ = false;
  uint64_t model_updates_ = 0, reconstructions_ = 0;
};

}  // namespace hd::station
