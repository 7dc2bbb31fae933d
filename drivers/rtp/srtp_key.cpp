#include "drivers/rtp/srtp_key.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>

#include "drivers/camera_source.h"

namespace hd::drivers {
namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool is_space(char c) {
  return c == ' ' || c == '\n' || c == '\r' || c == '\t';
}

}  // namespace

std::optional<SrtpKey> parse_srtp_key_text(std::string_view text, std::string& why) {
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  if (text.size() != 2 * kSrtpKeyBytes) {
    why = "expected " + std::to_string(2 * kSrtpKeyBytes) +
          " hex digits (a 16-byte AES-128-GCM key and its 12-byte salt), found " +
          std::to_string(text.size()) + " characters";
    return std::nullopt;
  }
  SrtpKey k;
  for (std::size_t i = 0; i < kSrtpKeyBytes; ++i) {
    const int hi = hex_value(text[2 * i]), lo = hex_value(text[2 * i + 1]);
    if (hi < 0 || lo < 0) {
      why = "character " + std::to_string(2 * i + (hi < 0 ? 1 : 2)) + " is not a hex digit";
      return std::nullopt;
    }
    k.bytes[i] = static_cast<uint8_t>(hi * 16 + lo);
  }
  return k;
}

SrtpKey read_srtp_key_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw DeviceError("key file " + path + ": cannot be read");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw DeviceError("key file " + path + ": not a regular file");
  }
  if ((st.st_mode & 077) != 0) {
    ::close(fd);
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw DeviceError("key file " + path + ": mode " + mode +
                      " lets others read or change it; refused (chmod 600 " + path + ")");
  }
  char buf[256];
  const ssize_t n = ::read(fd, buf, sizeof buf);
  ::close(fd);
  if (n < 0) throw DeviceError("key file " + path + ": cannot be read");
  std::string why;
  auto key = parse_srtp_key_text(std::string_view(buf, static_cast<std::size_t>(n)), why);
  if (!key) throw DeviceError("key file " + path + ": " + why);
  key->file = path;
  return *key;
}

}  // namespace hd::drivers
