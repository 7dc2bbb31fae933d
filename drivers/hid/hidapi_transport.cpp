#include "drivers/hid/hidapi_transport.h"

#include <hidapi/hidapi.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace hd::drivers {
namespace {

bool hidapi_ready(std::string& why) {
  // hid_init is process-wide; hidapi cleans up at exit. A failed init (no udev in a container)
  // means "no HID devices", never a crash.
  static const int rc = hid_init();
  if (rc != 0) why = "hidapi initialisation failed (hid_init)";
  return rc == 0;
}

std::string narrow(const wchar_t* w) {
  std::string s;
  if (w == nullptr) return s;
  for (; *w != 0; ++w) s.push_back(*w > 0 && *w < 128 ? static_cast<char>(*w) : '?');
  return s;
}

std::string open_failure(const std::string& path, int err) {
  std::string why = "cannot open " + path;
  if (err == EACCES || err == EPERM) {
    why +=
        ": permission denied; install udev/70-hybrid-station.rules (docs/devices.md, "
        "\"Device access\") and replug";
  } else if (err != 0) {
    why += std::string(": ") + std::strerror(err);
  }
  return why;
}

}  // namespace

std::unique_ptr<HidapiTransport> HidapiTransport::open_path(const std::string& path,
                                                            std::string& why) {
  if (!hidapi_ready(why)) return nullptr;
  errno = 0;
  hid_device* d = hid_open_path(path.c_str());
  if (d == nullptr) {
    why = open_failure(path, errno);
    return nullptr;
  }
  return std::unique_ptr<HidapiTransport>(new HidapiTransport(d, path));
}

HidapiTransport::~HidapiTransport() {
  hid_close(device_);
}

int HidapiTransport::read_report(std::span<uint8_t> buffer, int timeout_ms) {
  return hid_read_timeout(device_, buffer.data(), buffer.size(), timeout_ms);
}

int HidapiTransport::get_feature_report(std::span<uint8_t> buffer) {
  return hid_get_feature_report(device_, buffer.data(), buffer.size());
}

int HidapiTransport::send_feature_report(std::span<const uint8_t> report) {
  return hid_send_feature_report(device_, report.data(), report.size());
}

std::string HidapiTransport::error() const {
  return path_ + ": " + narrow(hid_error(device_));
}

std::vector<HidDeviceEntry> enumerate_hid_devices() {
  std::vector<HidDeviceEntry> out;
  std::string why;
  if (!hidapi_ready(why)) return out;
  hid_device_info* list = hid_enumerate(0, 0);
  for (hid_device_info* d = list; d != nullptr; d = d->next) {
    HidDeviceEntry e;
    e.path = d->path != nullptr ? d->path : "";
    e.vendor_id = d->vendor_id;
    e.product_id = d->product_id;
    e.usage_page = d->usage_page;
    e.usage = d->usage;
    e.manufacturer = narrow(d->manufacturer_string);
    e.product = narrow(d->product_string);
    e.serial = narrow(d->serial_number);
    out.push_back(std::move(e));
  }
  hid_free_enumeration(list);
  return out;
}

bool is_head_tracker(const HidDeviceEntry& e) {
  if (e.usage_page == 0x20 && e.usage == 0xE1) return true;
  return e.vendor_id == 0x1532 && e.product_id == 0x0b00;
}

HidTransportOpener hidapi_opener(std::string path) {
  return [path](std::string& why) -> std::unique_ptr<HidTransport> {
    std::string target = path;
    if (target.empty()) {
      for (const auto& e : enumerate_hid_devices()) {
        if (is_head_tracker(e)) {
          target = e.path;
          break;
        }
      }
      if (target.empty()) {
        why = "no HID head tracker found (usage page 0x20 / usage 0xE1, or OSVR HDK 1532:0b00)";
        return nullptr;
      }
    }
    return HidapiTransport::open_path(target, why);
  };
}

std::vector<DeviceInfo> probe_hid_devices() {
  std::vector<DeviceInfo> out;
  for (const auto& e : enumerate_hid_devices()) {
    if (!is_head_tracker(e)) continue;
    DeviceInfo info;
    info.kind = "hid";
    info.id = e.path;
    char ids[16];
    std::snprintf(ids, sizeof ids, "%04x:%04x", e.vendor_id, e.product_id);
    info.description =
        (e.product.empty() ? std::string("HID head tracker") : e.product) + " " + ids;
    std::string why;
    info.openable = HidapiTransport::open_path(e.path, why) != nullptr;
    if (!info.openable) info.reason = why;
    out.push_back(std::move(info));
  }
  return out;
}

}  // namespace hd::drivers
