#pragma once
// Is a GigE Vision device still answering? One GVCP READREG with our own deadline.

#include <cstdint>
#include <string>

namespace hd::drivers {

/// Aravis's own GVCP requests retry for seconds and its heartbeat reports "control-lost" only
/// after several missed periods; the station must report a dead camera within 1 s. This probe
/// sends one read of a bootstrap register from its own UDP socket, connected to the device's
/// control port so a dead peer on a reachable host answers with ICMP "port unreachable" at once,
/// and gives up after `timeout_ns` when nothing answers (cable pulled, host gone).
class GvcpLivenessProbe {
 public:
  /// `ipv4` is the device's address in dotted form, `port` its GVCP port (3956).
  GvcpLivenessProbe(std::string ipv4, uint16_t port = 3956);
  ~GvcpLivenessProbe();
  GvcpLivenessProbe(const GvcpLivenessProbe&) = delete;
  GvcpLivenessProbe& operator=(const GvcpLivenessProbe&) = delete;

  enum class Answer : uint8_t { kAlive, kRefused, kTimeout, kError };

  /// Sends READREG(0x0000, the GigE Vision version register) and waits for the matching ack.
  Answer ping(int64_t timeout_ns);

  const std::string& last_error() const { return last_error_; }

 private:
  std::string ipv4_;
  uint16_t port_;
  int fd_ = -1;
  uint16_t request_id_ = 0x4000;
  std::string last_error_;
};

}  // namespace hd::drivers
