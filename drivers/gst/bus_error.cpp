// parse_bus_error: a GStreamer error message as three strings.
#include "drivers/gst/bus_error.h"

#include "drivers/gobject_ptr.h"

namespace hd::drivers {

std::string BusError::to_string() const {
  return source.empty() ? text : source + ": " + text;
}

std::optional<BusError> parse_bus_error(GstMessage* message) {
  if (message == nullptr || GST_MESSAGE_TYPE(message) != GST_MESSAGE_ERROR) return std::nullopt;
  GError* error = nullptr;
  gchar* debug = nullptr;
  gst_message_parse_error(message, &error, &debug);
  const GCharPtr owned_debug(debug);
  BusError e;
  if (GST_MESSAGE_SRC(message) != nullptr && GST_MESSAGE_SRC_NAME(message) != nullptr)
    e.source = GST_MESSAGE_SRC_NAME(message);
  e.text = error != nullptr && error->message != nullptr ? error->message : "error";
  if (debug != nullptr) e.debug = debug;
  g_clear_error(&error);
  return e;
}

}  // namespace hd::drivers
