#pragma once
// How much a GigE stream is given to absorb a busy host: the kernel socket buffer, the Aravis
// buffer pool and how long Aravis waits for resent packets.

#include <cstddef>
#include <cstdint>

namespace hd::drivers {

/// The socket buffer for a stream of `payload_bytes` frames at `frame_rate_hz`: `configured_bytes`
/// when > 0; else 100 ms of frames (at least 4 frames), at most 64 MiB. A scheduling hiccup of
/// the stream thread then fills the buffer instead of dropping packets.
int socket_buffer_bytes_for(int configured_bytes, std::size_t payload_bytes, double frame_rate_hz);

/// Aravis buffers to allocate: `configured` unless it is 0; else every frame that can be in flight
/// while Aravis retains an incomplete one for `frame_retention_ns` (frames at `frame_rate_hz`),
/// plus 4 for the consumer's side, at least 8.
int buffer_count_for(int configured, double frame_rate_hz, int64_t frame_retention_ns);

/// Aravis's "frame-retention" property (us) for `frame_retention_ns`, clamped to 1 ms .. 10 s.
unsigned frame_retention_us_for(int64_t frame_retention_ns);

}  // namespace hd::drivers
