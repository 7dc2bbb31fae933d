#pragma once
// The station's one clock (DESIGN.md "Conventions"): CLOCK_MONOTONIC in integer nanoseconds.

#include <cstdint>

namespace hd::drivers {

/// CLOCK_MONOTONIC now, in nanoseconds. Never jumps with NTP or wall-clock changes.
int64_t monotonic_now_ns();

/// CLOCK_REALTIME - CLOCK_MONOTONIC of this host now, ns (realtime against the midpoint of two
/// monotonic reads around it, the tightest of three tries: within a microsecond or so): what maps
/// a sender's wall-clock stamp onto this host's clock when both run on one host, or when the sites'
/// clocks are synchronised (chrony/PTP).
int64_t realtime_minus_monotonic_ns();

}  // namespace hd::drivers
