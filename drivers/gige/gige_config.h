#pragma once
// What the station asks of one GigE Vision camera.

#include <cstdint>
#include <string>

#include "drivers/frame.h"

namespace hd::drivers {

/// Sensor region in device pixels (after binning); width 0 keeps the camera's current region. A
/// negative offset keeps the camera's current offset on that axis when the region still fits on
/// the sensor there, else uses 0 (what negotiate() asks for: hybrid-calib keeps the camera's
/// region, so the station keeps the offset the calibration saw).
struct GigeRoi {
  int x_px = 0;
  int y_px = 0;
  int width_px = 0;
  int height_px = 0;
};

struct GigeConfig {
  std::string
      device_id;  ///< Aravis id ("Aravis-Fake-SERIAL", "<vendor>-<serial>") or an IP address
  PixelFormat pixel_format = PixelFormat::kMono8;  ///< Mono8, RGB8 or one of the 8-bit Bayers
  GigeRoi roi;
  /// Binning factors (BinningHorizontal / BinningVertical); 0 keeps the camera's binning. Set
  /// before the region, whose sizes are binned pixels.
  int binning_x = 0;
  int binning_y = 0;
  double frame_rate_hz = 30.0;  ///< 0 keeps the camera's rate
  int packet_size_bytes = 0;    ///< 0: negotiate the largest the path carries
  /// Aravis buffers allocated at open and recycled. 0: enough for every frame that can be in
  /// flight during `frame_retention_ns`, plus 4 (at least 8).
  int buffer_count = 0;
  /// Kernel receive buffer for the stream socket; 0 sizes it for 100 ms of frames (at least 4
  /// frames), so a scheduling hiccup of the stream thread does not drop packets at 60 fps.
  int socket_buffer_bytes = 0;
  /// How long Aravis keeps an incomplete frame waiting for missing (resent) packets before it
  /// gives up with ARV_BUFFER_STATUS_TIMEOUT. Aravis's 100 ms default loses frames when a busy
  /// host starves its stream thread; a late frame still carries its own timestamps.
  int64_t frame_retention_ns = 300'000'000;
  int64_t stall_timeout_ns = 250'000'000;     ///< no frame for this long: stalled, then probed
  int64_t liveness_timeout_ns = 250'000'000;  ///< one GVCP probe's deadline
  /// Use Aravis's packet socket (a raw AF_PACKET receiver) when the process may. It never sees
  /// loopback traffic, so it is switched off for 127.0.0.0/8 regardless.
  bool allow_packet_socket = true;
};

}  // namespace hd::drivers
