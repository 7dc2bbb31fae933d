#pragma once
// What a GStreamer error message on a bus says, read in one place (the network camera's bus
// thread and start check, hybrid-remote's encoder probe).

#include <gst/gst.h>

#include <optional>
#include <string>

namespace hd::drivers {

struct BusError {
  std::string source;  ///< the posting element's name ("" when the message has no source)
  std::string text;    ///< the GError's message ("error" when it carries none)
  std::string debug;   ///< the debug detail ("" none): file, function, the element's reasons
  /// "source: text" (just the text without a source), as logs and reports show it.
  std::string to_string() const;
};

/// The error `message` carries; nullopt when it is not a GST_MESSAGE_ERROR (or null).
std::optional<BusError> parse_bus_error(GstMessage* message);

}  // namespace hd::drivers
