#pragma once
// libusb enumeration and hotplug for a list of vendor/product ids, so a tracker or camera plugged
// in after start-up is picked up. Uses libusb's hotplug callbacks where the platform has them,
// else re-enumerates periodically and reports the difference.

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "drivers/device_info.h"
#include "drivers/usb/usb_id.h"

struct libusb_context;
struct libusb_device;

namespace hd::drivers {

struct UsbDeviceEntry {
  int bus = 0;
  int address = 0;
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  std::string product;  ///< empty when the device could not be opened to read it
  bool openable = false;
  std::string reason;  ///< why it cannot be opened
};

enum class UsbEventKind : uint8_t { kArrived, kLeft };
struct UsbEvent {
  UsbEventKind kind;
  int bus;
  int address;
  uint16_t vendor_id;
  uint16_t product_id;
};

class UsbWatcher {
 public:
  using Callback = std::function<void(const UsbEvent&)>;
  /// `ids`: the devices to watch (empty: every device). Never throws: when libusb cannot start
  /// (no /dev/bus/usb in a container) available() is false and reason() says why.
  explicit UsbWatcher(std::vector<UsbId> ids,
                      std::chrono::milliseconds poll_interval = std::chrono::milliseconds(1000));
  ~UsbWatcher();
  UsbWatcher(const UsbWatcher&) = delete;
  UsbWatcher& operator=(const UsbWatcher&) = delete;

  bool available() const { return context_ != nullptr; }
  const std::string& reason() const { return reason_; }
  bool uses_hotplug_callbacks() const { return hotplug_; }

  /// Matching devices present now, each tried for opening (permission) once.
  std::vector<UsbDeviceEntry> enumerate();

  /// Starts the watch thread; `callback` runs on it for every matching arrival or departure
  /// (devices present at start are reported as arrivals).
  void start(Callback callback);
  void stop();

  /// Called from libusb's hotplug callback (on the watch thread): filters and forwards.
  void deliver(const UsbEvent& event);

 private:
  void run();
  void poll_once();

  std::vector<UsbId> ids_;
  std::chrono::milliseconds poll_interval_;
  libusb_context* context_ = nullptr;
  std::string reason_;
  bool hotplug_ = false;
  int hotplug_handle_ = 0;
  bool hotplug_registered_ = false;
  Callback callback_;
  std::atomic<bool> running_{false};
  std::thread thread_;
  std::set<std::pair<int, int>> present_;  // (bus, address), poll mode only
};

/// One DeviceInfo per matching USB device (kind "usb"), for `hybrid-station devices`.
std::vector<DeviceInfo> probe_usb_devices(const std::vector<UsbId>& ids);

}  // namespace hd::drivers
