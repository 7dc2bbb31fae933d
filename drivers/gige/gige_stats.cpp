// GigeCounters' snapshot into the plain GigeStats the station reads.
#include "drivers/gige/gige_stats.h"

namespace hd::drivers {

GigeStats GigeCounters::snapshot() const {
  GigeStats s;
  s.frames_published = frames_published.load(std::memory_order_relaxed);
  s.bad_buffers = bad_buffers.load(std::memory_order_relaxed);
  s.id_gaps = id_gaps.load(std::memory_order_relaxed);
  s.late_or_duplicate = late_or_duplicate.load(std::memory_order_relaxed);
  s.malformed = malformed.load(std::memory_order_relaxed);
  s.wrong_format = wrong_format.load(std::memory_order_relaxed);
  s.liveness_probes = liveness_probes.load(std::memory_order_relaxed);
  s.last_bad_status = last_bad_status.load(std::memory_order_relaxed);
  s.reconnects = reconnects.load(std::memory_order_relaxed);
  s.reopen_attempts = reopen_attempts.load(std::memory_order_relaxed);
  s.bad_before_first_frame = bad_before_first_frame.load(std::memory_order_relaxed);
  s.gaps_before_first_frame = gaps_before_first_frame.load(std::memory_order_relaxed);
  return s;
}

}  // namespace hd::drivers
