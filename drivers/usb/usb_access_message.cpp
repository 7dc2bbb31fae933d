#include "drivers/usb/usb_access_message.h"

#include <cstdio>

#include "drivers/usb/usb_id.h"

namespace hd::drivers {

std::string usb_access_denied_message(int bus, int address, uint16_t vendor_id, uint16_t product_id,
                                      const std::string& product) {
  char where[64];
  std::snprintf(where, sizeof where, "bus %03d device %03d", bus, address);
  std::string msg = std::string("USB ") + where + " (" + to_string(vendor_id, product_id);
  if (!product.empty()) msg += " \"" + product + "\"";
  msg +=
      "): permission denied. Install udev/70-hybrid-station.rules (see docs/devices.md, "
      "\"Device access\"): sudo install -m644 udev/70-hybrid-station.rules /etc/udev/rules.d/ && "
      "sudo udevadm control --reload && sudo udevadm trigger, then replug the device.";
  return msg;
}

}  // namespace hd::drivers
