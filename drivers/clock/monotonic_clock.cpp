#include "drivers/clock/monotonic_clock.h"

#include <ctime>

namespace hd::drivers {

int64_t monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int64_t realtime_minus_monotonic_ns() {
  // CLOCK_REALTIME read between two CLOCK_MONOTONIC reads, against their midpoint, and the
  // tightest of three tries kept. Read back to back once, a preemption between the two reads
  // (milliseconds on a saturated machine) biased the offset by its length, and a frame sent on
  // this host then seemed captured after it arrived (RemoteFaults under load).
  int64_t best = 0, best_gap = -1;
  for (int i = 0; i < 3; ++i) {
    timespec m0{}, r{}, m1{};
    clock_gettime(CLOCK_MONOTONIC, &m0);
    clock_gettime(CLOCK_REALTIME, &r);
    clock_gettime(CLOCK_MONOTONIC, &m1);
    const int64_t a = int64_t(m0.tv_sec) * 1'000'000'000LL + m0.tv_nsec;
    const int64_t b = int64_t(m1.tv_sec) * 1'000'000'000LL + m1.tv_nsec;
    const int64_t real = int64_t(r.tv_sec) * 1'000'000'000LL + r.tv_nsec;
    if (best_gap < 0 || b - a < best_gap) {
      best_gap = b - a;
      best = real - (a + (b - a) / 2);
    }
  }
  return best;
}

}  // namespace hd::drivers
