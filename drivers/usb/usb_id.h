#pragma once
// Vendor/product ids the station watches for, and matching against them.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hd::drivers {

struct UsbId {
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  std::string label;  ///< what it is, for messages
  bool operator==(const UsbId& o) const {
    return vendor_id == o.vendor_id && product_id == o.product_id;
  }
};

/// "1532:0b00" (hex, as lsusb prints it) -> id; nullopt for anything else.
std::optional<UsbId> parse_usb_id(std::string_view text);
std::string to_string(uint16_t vendor_id, uint16_t product_id);  ///< "1532:0b00"

/// True when (vid, pid) is in `ids`; an empty list matches nothing.
bool matches(std::span<const UsbId> ids, uint16_t vendor_id, uint16_t product_id);

/// Devices the station knows by id (the Android head tracker has no fixed id: it is found by its
/// HID usage instead, see hidapi_transport.h).
std::vector<UsbId> known_usb_ids();

}  // namespace hd::drivers
