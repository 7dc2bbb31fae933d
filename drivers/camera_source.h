#pragma once
// The one interface every camera (V4L2, GigE, mock) offers the station.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "drivers/camera_format.h"
#include "drivers/format_event.h"
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

/// A camera. open() (or negotiate()) sets the format, start() begins streaming on the driver's
/// own thread, which converts each frame to RGBA8 and publishes it into `frames()`. The consumer
/// fetches the newest frame without locks or allocation.
///
/// Format contract: every frame published into `frames()` has the size negotiated at open.
/// When the device delivers another size or pixel format during the run (a source change, a
/// reconnect with other settings, a frame of another size), state() becomes kFormatMismatch at
/// once, nothing is published, and a FormatEvent with its time goes to pop_format_event(); when
/// the negotiated format is back, state() leaves kFormatMismatch and a kRestored event follows.
class CameraSource {
 public:
  virtual ~CameraSource() = default;
  virtual std::string id() const = 0;  ///< stable identifier, e.g. "/dev/video0", "Aravis-Fake-X"
  /// Opens with the driver's own configuration.
  virtual void open() = 0;
  /// Opens asking the device for `wanted` (the station asks for the calibrated size) and returns
  /// what the device delivers, read back from it. A format the device cannot deliver is not an
  /// error here: the answer says what it delivers instead and why (judge_format() decides);
  /// DeviceError is for a device that cannot be opened at all. The default suits sources whose
  /// format is fixed: open(), then format().
  virtual FormatNegotiation negotiate(const CameraFormatRequest& wanted) {
    (void)wanted;
    open();
    return {format(), "", "", ""};
  }
  /// What the device delivers (after open()); unknown (width 0) where the source cannot say.
  virtual CameraFormat format() const { return {}; }
  /// The oldest format event not taken yet (single consumer). Never blocks or allocates.
  virtual bool pop_format_event(FormatEvent& out) {
    (void)out;
    return false;
  }
  virtual void start() = 0;
  virtual void stop() = 0;
  virtual SourceState state() const = 0;
  virtual uint64_t dropped_frames() const = 0;  ///< from device sequence gaps and bad buffers
  virtual Mailbox<Frame>& frames() = 0;
};

}  // namespace hd::drivers
