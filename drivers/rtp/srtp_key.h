#pragma once
// The pre-shared SRTP key of one stream (AES-128-GCM: a 16-byte key and a 12-byte salt) and its
// file: hex text, readable by its owner only. The key's bytes never appear in a message.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace hd::drivers {

inline constexpr std::size_t kSrtpKeyBytes = 28;  ///< AES-128-GCM master key 16 + salt 12

struct SrtpKey {
  std::array<uint8_t, kSrtpKeyBytes> bytes{};
  std::string file;  ///< where it was read from, for reports (never the key itself)
};

/// Parses 56 hex digits (whitespace around them allowed). On failure sets `why` (which never
/// quotes the text) and returns nullopt.
std::optional<SrtpKey> parse_srtp_key_text(std::string_view text, std::string& why);

/// Reads a key file. Throws DeviceError naming the file when it cannot be read, when its group or
/// others may read or write it (the message gives its mode and `chmod 600 FILE`), or when its
/// content is not one key.
SrtpKey read_srtp_key_file(const std::string& path);

}  // namespace hd::drivers
