// GigE stream sizing: socket buffer, Aravis buffer pool and frame retention.
#include "drivers/gige/stream_sizing.h"

#include <algorithm>
#include <cmath>

namespace hd::drivers {

int socket_buffer_bytes_for(int configured_bytes, std::size_t payload_bytes, double frame_rate_hz) {
  if (configured_bytes > 0) return configured_bytes;
  const auto frames_100ms = static_cast<std::size_t>(std::ceil(frame_rate_hz * 0.1));
  return static_cast<int>(
      std::min<std::size_t>(payload_bytes * std::max<std::size_t>(4, frames_100ms), 64u << 20));
}

int buffer_count_for(int configured, double frame_rate_hz, int64_t frame_retention_ns) {
  if (configured != 0) return configured;
  const double in_flight = frame_rate_hz * static_cast<double>(frame_retention_ns) * 1e-9;
  return std::max(8, static_cast<int>(std::ceil(in_flight)) + 4);
}

unsigned frame_retention_us_for(int64_t frame_retention_ns) {
  return static_cast<unsigned>(std::clamp<int64_t>(frame_retention_ns / 1000, 1000, 10'000'000));
}

}  // namespace hd::drivers
