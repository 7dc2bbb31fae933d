#pragma once
// A camera stopped (or started again) delivering the format the station negotiated at open: the
// record a driver leaves for the station to report, with its time.

#include <cstdint>
#include <string_view>

#include "drivers/camera_format.h"
#include "drivers/spsc_ring.h"

namespace hd::drivers {

enum class FormatEventKind : uint8_t {
  kLost,      ///< the device delivers another format: the camera is unusable (kFormatMismatch)
  kRestored,  ///< it delivers the negotiated format again
};

/// How the driver found out.
enum class FormatEventCause : uint8_t {
  kFrame,         ///< a frame of another size or pixel format arrived (it was not published)
  kSourceChange,  ///< the device said so (V4L2_EVENT_SOURCE_CHANGE)
  kReconnect,     ///< the device came back (reconnect, replug) with other settings
};

struct FormatEvent {
  int64_t time_ns = 0;  ///< CLOCK_MONOTONIC, when the driver saw it
  FormatEventKind kind = FormatEventKind::kLost;
  FormatEventCause cause = FormatEventCause::kFrame;
  CameraFormat expected;  ///< what was negotiated at open (and what the mailbox is sized for)
  CameraFormat seen;      ///< what the device delivers now (size unknown: it did not say)
};

/// Device thread -> station; a full ring drops the newest event and counts it (overflowed()).
using FormatEventRing = SpscRing<FormatEvent, 64>;

inline std::string_view to_string(FormatEventKind k) {
  return k == FormatEventKind::kLost ? "format lost" : "format restored";
}

inline std::string_view to_string(FormatEventCause c) {
  switch (c) {
    case FormatEventCause::kFrame:
      return "frame";
    case FormatEventCause::kSourceChange:
      return "source change";
    case FormatEventCause::kReconnect:
      return "reconnect";
  }
  return "unknown";
}

}  // namespace hd::drivers
