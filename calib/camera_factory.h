#pragma once
// Turns a --camera id into the driver that serves it, so the calibration tool takes the same ids
// as the station: "/dev/videoN" (V4L2), "mock" or "mock:WxH" (generated frames), anything else a
// GigE Vision id for Aravis (e.g. "Aravis-Fake-SERIAL", "<vendor>-<serial>", an IP address);
// "rtp://HOST:PORT" the network camera (an RTP H.264 stream the station listens for);
// "replay:DIR/GLOB[@RATE_HZ[+-OFFSET_MS]]" recorded pictures played as a camera.

#include <memory>
#include <string>

#include "drivers/camera_source.h"

namespace hd::calib {

enum class CameraKind { kV4l2, kMock, kGige, kRtp, kReplay };

/// A replay id taken apart: `replay:DIR/GLOB[@RATE_HZ[+-OFFSET_MS]]`, e.g.
/// `replay:data/calib/opencv-left/left*.jpg@15` or `...right*.jpg@15+50` (50 ms late). GLOB is
/// matched as `intrinsics --pattern` is (sorted by name); a bare folder plays all its images.
struct ReplayId {
  std::string folder;
  std::string pattern = "*";
  double rate_hz = 15.0;
  double offset_ms = 0.0;
};

/// Parses a replay id; throws std::invalid_argument naming the id and what is expected.
ReplayId parse_replay_id(const std::string& id);

/// Which driver `id` names. Never throws; an empty id is a GigE id that will fail to open.
CameraKind camera_kind(const std::string& id);

/// The unopened source for `id`. Throws std::invalid_argument for a malformed mock size and
/// drivers::DeviceError when the driver for that kind is not built into this program; open()
/// and start() throw DeviceError (naming the device) when the device cannot be used.
std::unique_ptr<drivers::CameraSource> make_camera_source(const std::string& id);

/// Releases process-wide driver state (Aravis's interface list) once every source is gone, so
/// leak checkers see only real leaks.
void shutdown_camera_drivers();

}  // namespace hd::calib
