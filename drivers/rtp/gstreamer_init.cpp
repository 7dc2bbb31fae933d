#include "drivers/rtp/gstreamer_init.h"

#include <gst/gst.h>

#include <mutex>
#include <string>

#include "drivers/camera_source.h"

namespace hd::drivers {

void ensure_gstreamer() {
  static std::once_flag once;
  static std::string failure;
  std::call_once(once, [] {
    GError* e = nullptr;
    if (!gst_init_check(nullptr, nullptr, &e))
      failure = std::string("GStreamer failed to start: ") + (e != nullptr ? e->message : "?");
    g_clear_error(&e);
  });
  if (!failure.empty()) throw DeviceError(failure);
}

}  // namespace hd::drivers
