#pragma once
// Turns a camera id into the driver that serves it, so the station, the remote site and the
// calibration tool take the same ids: "/dev/videoN" (V4L2), "mock" or "mock:WxH" (generated
// frames), anything else a GigE Vision id for Aravis (e.g. "Aravis-Fake-SERIAL",
// "<vendor>-<serial>", an IP address); "rtp://HOST:PORT" the network camera (an RTP H.264 stream
// the station listens for); "replay:DIR/GLOB[@RATE_HZ[+-OFFSET_MS]]" recorded pictures played as
// a camera (drivers/replay).
//
// The replay pictures are image files, and decoding them is not a driver's job: the replay driver
// takes its pictures from a loader callback and decodes nothing, and the reader the programs use
// (calib/image_set.h: libjpeg-turbo, libpng, libtiff, all-or-nothing with the bad file's name) sits
// above drivers/. So the caller passes that reader in (calib/replay_images.h has the one the
// programs use); without one, a replay id is refused as a driver that is not built in would be.
// A loader argument rather than a process-wide registration: what a call can open is visible at
// the call, and a test can hand in pictures from memory.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "drivers/camera_source.h"
#include "drivers/replay/replay_camera.h"

namespace hd::drivers {

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

/// Reads the pictures of a replay id, in play order, all one size (ReplayCameraConfig::load: the
/// camera calls it from open(), and a throw becomes a DeviceError naming the id).
using ReplayImageLoader = std::function<std::vector<ReplayImage>(const ReplayId&)>;

/// Which driver `id` names. Never throws; an empty id is a GigE id that will fail to open.
CameraKind camera_kind(const std::string& id);

/// The unopened source for `id`. Throws std::invalid_argument for a malformed id (mock size, rtp
/// address, replay rate) and DeviceError when the driver for that kind is not built into this
/// program, or for a replay id when `load_replay` is empty; open() and start() throw DeviceError
/// (naming the device) when the device cannot be used. Replay cameras made here share one epoch
/// (the first one's start): a rig on one trigger.
std::unique_ptr<CameraSource> make_camera_source(const std::string& id,
                                                 const ReplayImageLoader& load_replay = {});

/// Releases process-wide driver state (Aravis's interface list) once every source is gone, so
/// leak checkers see only real leaks.
void shutdown_camera_drivers();

}  // namespace hd::drivers
