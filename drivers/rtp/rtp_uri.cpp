#include "drivers/rtp/rtp_uri.h"

#include <cctype>
#include <charconv>

namespace hd::drivers {

bool is_rtp_id(std::string_view id) {
  return id.substr(0, kRtpScheme.size()) == kRtpScheme;
}

std::optional<RtpAddress> parse_rtp_uri(std::string_view id, std::string& why) {
  const std::string example = " (expected rtp://HOST:PORT, e.g. rtp://127.0.0.1:5600)";
  if (!is_rtp_id(id)) {
    why = "'" + std::string(id) + "' is not an rtp:// id" + example;
    return std::nullopt;
  }
  const std::string_view rest = id.substr(kRtpScheme.size());
  const std::size_t colon = rest.rfind(':');
  if (colon == std::string_view::npos || colon == 0 || colon + 1 >= rest.size()) {
    why = "'" + std::string(id) + "' has no host or no port" + example;
    return std::nullopt;
  }
  const std::string_view host = rest.substr(0, colon), port_text = rest.substr(colon + 1);
  for (const char c : host)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-')) {
      why = "'" + std::string(id) + "': host '" + std::string(host) +
            "' may hold only letters, digits, '.' and '-'" + example;
      return std::nullopt;
    }
  unsigned port = 0;
  const auto [end, ec] =
      std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (ec != std::errc() || end != port_text.data() + port_text.size() || port < 1024 ||
      port > 65534 || port % 2 != 0) {
    why = "'" + std::string(id) + "': port '" + std::string(port_text) +
          "' must be an even number 1024..65534 (RTCP uses the next one)" + example;
    return std::nullopt;
  }
  return RtpAddress{std::string(host), static_cast<uint16_t>(port)};
}

std::string to_uri(const RtpAddress& a) {
  return std::string(kRtpScheme) + a.host + ":" + std::to_string(a.port);
}

}  // namespace hd::drivers
