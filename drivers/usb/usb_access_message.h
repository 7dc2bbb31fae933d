#pragma once
// The one message a user sees when a USB device exists but this user may not open it.

#include <cstdint>
#include <string>

namespace hd::drivers {

/// Names the device (bus/address, VID:PID, product string when readable) and says how to fix it.
std::string usb_access_denied_message(int bus, int address, uint16_t vendor_id, uint16_t product_id,
                                      const std::string& product);

}  // namespace hd::drivers
