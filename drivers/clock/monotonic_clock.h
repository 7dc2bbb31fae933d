#pragma once
// The station's one clock (DESIGN.md "Conventions"): CLOCK_MONOTONIC in integer nanoseconds.

#include <cstdint>

namespace hd::drivers {

/// CLOCK_MONOTONIC now, in nanoseconds. Never jumps with NTP or wall-clock changes.
int64_t monotonic_now_ns();

}  // namespace hd::drivers
