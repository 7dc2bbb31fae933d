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
  /// The device delivers another size or pixel format than the one negotiated at open (a source
  /// change, a reconnect with other settings): no frame is published until it delivers the
  /// negotiated one again.
  kFormatMismatch,
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
    case SourceState::kFormatMismatch:
      return "format-mismatch";
  }
  return "unknown";
}

}  // namespace hd::drivers
