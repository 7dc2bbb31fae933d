#include "drivers/usb/usb_id.h"

#include <algorithm>
#include <charconv>
#include <cstdio>

namespace hd::drivers {

std::optional<UsbId> parse_usb_id(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos || colon == 0 || colon > 4 || text.size() - colon - 1 == 0 ||
      text.size() - colon - 1 > 4)
    return std::nullopt;
  const auto parse = [](std::string_view s, uint16_t& out) {
    unsigned v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v, 16);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || v > 0xFFFF) return false;
    out = static_cast<uint16_t>(v);
    return true;
  };
  UsbId id;
  if (!parse(text.substr(0, colon), id.vendor_id) || !parse(text.substr(colon + 1), id.product_id))
    return std::nullopt;
  return id;
}

std::string to_string(uint16_t vendor_id, uint16_t product_id) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04x:%04x", vendor_id, product_id);
  return buf;
}

bool matches(std::span<const UsbId> ids, uint16_t vendor_id, uint16_t product_id) {
  return std::any_of(ids.begin(), ids.end(), [&](const UsbId& id) {
    return id.vendor_id == vendor_id && id.product_id == product_id;
  });
}

std::vector<UsbId> known_usb_ids() {
  return {
      {0x1532, 0x0b00, "OSVR HDK head tracker (Razer)"},
  };
}

}  // namespace hd::drivers
