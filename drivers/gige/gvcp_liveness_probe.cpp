#include "drivers/gige/gvcp_liveness_probe.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "drivers/clock/monotonic_clock.h"

namespace hd::drivers {

namespace {
constexpr uint8_t kGvcpKey = 0x42;
constexpr uint8_t kFlagAckRequired = 0x01;
constexpr uint16_t kReadRegCmd = 0x0080;
constexpr uint16_t kReadRegAck = 0x0081;
constexpr uint32_t kVersionRegister = 0x0000;
}  // namespace

GvcpLivenessProbe::GvcpLivenessProbe(std::string ipv4, uint16_t port)
    : ipv4_(std::move(ipv4)), port_(port) {}

GvcpLivenessProbe::~GvcpLivenessProbe() {
  if (fd_ >= 0) ::close(fd_);
}

GvcpLivenessProbe::Answer GvcpLivenessProbe::ping(int64_t timeout_ns) {
  if (fd_ < 0) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd_ < 0) {
      last_error_ = std::string("socket: ") + std::strerror(errno);
      return Answer::kError;
    }
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(port_);
    if (::inet_pton(AF_INET, ipv4_.c_str(), &addr.sin_addr) != 1) {
      last_error_ = "not an IPv4 address: '" + ipv4_ + "'";
      ::close(fd_);
      fd_ = -1;
      return Answer::kError;
    }
    if (::connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
      last_error_ = std::string("connect: ") + std::strerror(errno);
      ::close(fd_);
      fd_ = -1;
      return Answer::kError;
    }
  }
  // Drain stale acks (and pending ICMP errors) from an earlier, timed-out ping.
  std::array<uint8_t, 64> rx{};
  while (::recv(fd_, rx.data(), rx.size(), 0) >= 0 || errno == ECONNREFUSED) {
  }

  const uint16_t id = ++request_id_ == 0 ? ++request_id_ : request_id_;
  std::array<uint8_t, 12> tx{kGvcpKey,
                             kFlagAckRequired,
                             static_cast<uint8_t>(kReadRegCmd >> 8),
                             static_cast<uint8_t>(kReadRegCmd & 0xff),
                             0,
                             4,
                             static_cast<uint8_t>(id >> 8),
                             static_cast<uint8_t>(id & 0xff),
                             static_cast<uint8_t>(kVersionRegister >> 24),
                             static_cast<uint8_t>(kVersionRegister >> 16),
                             static_cast<uint8_t>(kVersionRegister >> 8),
                             static_cast<uint8_t>(kVersionRegister)};
  if (::send(fd_, tx.data(), tx.size(), 0) < 0) {
    if (errno == ECONNREFUSED) return Answer::kRefused;
    last_error_ = std::string("send: ") + std::strerror(errno);
    return Answer::kError;
  }
  const int64_t deadline_ns = monotonic_now_ns() + timeout_ns;
  for (;;) {
    const int64_t left_ns = deadline_ns - monotonic_now_ns();
    if (left_ns <= 0) return Answer::kTimeout;
    pollfd p{fd_, POLLIN, 0};
    const int n = ::poll(&p, 1, static_cast<int>((left_ns + 999'999) / 1'000'000));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return Answer::kTimeout;
    const ssize_t got = ::recv(fd_, rx.data(), rx.size(), 0);
    if (got < 0) {
      if (errno == ECONNREFUSED) return Answer::kRefused;
      if (errno == EAGAIN || errno == EINTR) continue;
      last_error_ = std::string("recv: ") + std::strerror(errno);
      return Answer::kError;
    }
    // Ack header: status(2) answer(2) length(2) ack_id(2). Anything else is not ours.
    if (got >= 8 && ((rx[2] << 8) | rx[3]) == kReadRegAck && ((rx[6] << 8) | rx[7]) == id) {
      return Answer::kAlive;
    }
  }
}

}  // namespace hd::drivers
