#pragma once
// GStreamer's one-time process initialisation for the network camera and hybrid-remote.

namespace hd::drivers {

/// gst_init once per process (thread-safe); throws DeviceError when GStreamer cannot start.
void ensure_gstreamer();

}  // namespace hd::drivers
