#pragma once
// The one interface every camera (V4L2, GigE, mock) offers the station.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "drivers/frame.h"
#include "drivers/mailbox.h"
#include "drivers/source_state.h"

namespace hd::drivers {

/// Thrown by open()/start() (never on the per-frame path); the message names the device and says
/// what was expected.
class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A camera. open() negotiates the format, start() begins streaming on the driver's own thread,
/// which converts each frame to RGBA8 and publishes it into `frames()`. The consumer fetches the
/// newest frame without locks or allocation.
class CameraSource {
 public:
  virtual ~CameraSource() = default;
  virtual std::string id() const = 0;  ///< stable identifier, e.g. "/dev/video0", "Aravis-Fake-X"
  virtual void open() = 0;
  virtual void start() = 0;
  virtual void stop() = 0;
  virtual SourceState state() const = 0;
  virtual uint64_t dropped_frames() const = 0;  ///< from device sequence gaps and bad buffers
  virtual Mailbox<Frame>& frames() = 0;
};

}  // namespace hd::drivers
