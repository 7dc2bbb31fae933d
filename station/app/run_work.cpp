#include "station/app/run_work.h"

#include "core/allocation_counter.h"

namespace hd::station {

void RunWork::tick(const render::FrameTiming& t) {
  core::count_allocations_on_this_thread(t.frame >= warmup_);
  frame_.tick(t);
  if (t.frame == 0) first_start_ns_ = t.start_ns;
  FrameLogRow row;
  row.decision = frame_.last_row();
  row.t_s = 1e-9 * static_cast<double>(t.start_ns - first_start_ns_);
  row.missed_deadline = latency_.size() > 0 && latency_.at(latency_.size() - 1).missed_deadline;
  log_.add(row);
  recorder_.offer(frame_.image(),
                  {t.frame, row.t_s, row.decision.variant, row.decision.m, row.decision.w_video});
  core::count_allocations_on_this_thread(false);
}

}  // namespace hd::station
