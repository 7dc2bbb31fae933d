#pragma once
// The scene's t = 0 shared by two processes (hybrid-remote renders the cameras, hybrid-station
// the head): one CLOCK_REALTIME instant given to both on the command line (`--scene-epoch`),
// mapped by each onto its own CLOCK_MONOTONIC, so the objects the remote's cameras see and the
// head the station moves follow one scene clock.

#include <cstdint>
#include <optional>
#include <string>

namespace hd::sim {

/// Parses `--scene-epoch`: seconds since the Unix epoch on CLOCK_REALTIME, with up to nine
/// decimals (as `date +%s.%N` prints), exactly into ns. nullopt (and `why`) when malformed.
std::optional<int64_t> parse_scene_epoch(const std::string& text, std::string& why);

/// A CLOCK_REALTIME instant (ns since the Unix epoch) on this host's CLOCK_MONOTONIC (ns), through
/// the two clocks' offset read now. Exact between processes of one host (they share both clocks);
/// across hosts as good as their realtime clocks agree (chrony/PTP).
int64_t realtime_to_monotonic_ns(int64_t realtime_ns);

/// The scene time at `monotonic_ns` for an epoch on CLOCK_MONOTONIC (s; negative before t = 0).
inline double scene_time_s(int64_t monotonic_ns, int64_t epoch_monotonic_ns) {
  return static_cast<double>(monotonic_ns - epoch_monotonic_ns) * 1e-9;
}

}  // namespace hd::sim
