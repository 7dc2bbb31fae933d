#pragma once
// The network camera's id: `rtp://HOST:PORT`, the station's listen address for one RTP stream.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace hd::drivers {

/// Where the station listens for one camera's RTP stream. RTP arrives on `port`; RTCP (from a
/// sender that sends it, e.g. hybrid-remote) on `port + 1`, the RFC 3550 convention.
struct RtpAddress {
  std::string host;   ///< a numeric IPv4 address or a host name; 0.0.0.0 listens on every interface
  uint16_t port = 0;  ///< even, 1024..65534
};

inline constexpr std::string_view kRtpScheme = "rtp://";

/// True when `id` uses the rtp:// scheme (whether or not the rest is well formed).
bool is_rtp_id(std::string_view id);

/// Parses `rtp://HOST:PORT`. On failure returns nullopt and sets `why` to a sentence naming what
/// is wrong and what is expected (`rtp://127.0.0.1:5600`).
std::optional<RtpAddress> parse_rtp_uri(std::string_view id, std::string& why);

/// `rtp://HOST:PORT`.
std::string to_uri(const RtpAddress& a);

}  // namespace hd::drivers
