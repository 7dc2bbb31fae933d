#include "drivers/clock/monotonic_clock.h"

#include <ctime>

namespace hd::drivers {

int64_t monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

int64_t realtime_minus_monotonic_ns() {
  timespec r{}, m{};
  clock_gettime(CLOCK_REALTIME, &r);
  clock_gettime(CLOCK_MONOTONIC, &m);
  return (int64_t(r.tv_sec) - int64_t(m.tv_sec)) * 1'000'000'000LL +
         (int64_t(r.tv_nsec) - int64_t(m.tv_nsec));
}

}  // namespace hd::drivers
