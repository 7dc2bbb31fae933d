#pragma once
// The seam between HidHeadTracker and the operating system: the real one is hidapi (hidraw),
// tests use FakeHidTransport, the simulator uses the mock head tracker.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

namespace hd::drivers {

class HidTransport {
 public:
  virtual ~HidTransport() = default;
  /// Reads one input report. Returns its length, 0 on timeout, -1 when the device failed or went
  /// away (see error()).
  virtual int read_report(std::span<uint8_t> buffer, int timeout_ms) = 0;
  /// `buffer[0]` holds the report id on entry. Returns the length read (id byte included), or -1.
  virtual int get_feature_report(std::span<uint8_t> buffer) = 0;
  /// `report[0]` is the report id. Returns the length written, or -1.
  virtual int send_feature_report(std::span<const uint8_t> report) = 0;
  virtual std::string error() const = 0;
};

/// Opens the device. Returns nullptr and fills `why` when it is absent or cannot be opened; the
/// tracker retries it while the device is away.
using HidTransportOpener = std::function<std::unique_ptr<HidTransport>(std::string& why)>;

}  // namespace hd::drivers
