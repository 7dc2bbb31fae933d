#pragma once

#include <cstdint>
#include <string_view>

namespace hd::drivers {

/// What a device is doing, as the render loop and `hybrid-station devices` see it.
enum class SourceState : uint8_t {
  kClosed,        ///< not opened, or stopped
  kStreaming,     ///< data arriving at the expected rate
  kStalled,       ///< open, but nothing new for longer than the stall timeout
  kDisconnected,  ///< the device went away; the driver reopens it when it returns
};

inline std::string_view to_string(SourceState s) {
  switch (s) {
    case SourceState::kClosed:
      return "closed";
    case SourceState::kStreaming:
      return "streaming";
    case SourceState::kStalled:
      return "stalled";
    case SourceState::kDisconnected:
      return "disconnected";
  }
  return "unknown";
}

}  // namespace hd::drivers
