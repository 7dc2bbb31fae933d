#pragma once
// HidTransport on hidapi's hidraw backend, and the enumeration `hybrid-station devices` uses.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "drivers/device_info.h"
#include "drivers/hid/hid_transport.h"

struct hid_device_;

namespace hd::drivers {

class HidapiTransport : public HidTransport {
 public:
  /// Opens a hidraw node (path from enumerate_hid_devices(), e.g. "/dev/hidraw3"). Returns
  /// nullptr and a reason naming the path (and the udev rules when it is a permission problem).
  static std::unique_ptr<HidapiTransport> open_path(const std::string& path, std::string& why);
  ~HidapiTransport() override;
  HidapiTransport(const HidapiTransport&) = delete;
  HidapiTransport& operator=(const HidapiTransport&) = delete;

  int read_report(std::span<uint8_t> buffer, int timeout_ms) override;
  int get_feature_report(std::span<uint8_t> buffer) override;
  int send_feature_report(std::span<const uint8_t> report) override;
  std::string error() const override;

 private:
  HidapiTransport(hid_device_* device, std::string path)
      : device_(device), path_(std::move(path)) {}
  hid_device_* device_;
  std::string path_;
};

struct HidDeviceEntry {
  std::string path;
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  uint16_t usage_page = 0;
  uint16_t usage = 0;
  std::string manufacturer;
  std::string product;
  std::string serial;
};

/// Every HID interface hidapi sees (empty when there is none or hidraw is unavailable).
std::vector<HidDeviceEntry> enumerate_hid_devices();

/// True for an Android head tracker collection (usage page 0x20, usage 0xE1) or an OSVR HDK
/// (1532:0b00). Other HID devices (keyboards, mice) are not trackers.
bool is_head_tracker(const HidDeviceEntry& entry);

/// Opens the first head tracker found (or the given hidraw path when `path` is not empty).
HidTransportOpener hidapi_opener(std::string path = {});

/// One DeviceInfo per head tracker interface, with whether this process can open it and why not.
std::vector<DeviceInfo> probe_hid_devices();

}  // namespace hd::drivers
