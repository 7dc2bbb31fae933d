// The receive sockets' buffers and kernel drops: the report's text, the probe, and the reads of
// SO_RCVBUF, /proc/sys/net/core/rmem_max and /proc/net/udp.
#include "drivers/rtp/rtp_receive_socket.h"

#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <fstream>
#include <sstream>
#include <vector>

namespace hd::drivers {
namespace {

std::string bytes(int64_t n) {
  return std::to_string(n) + " B";
}

int64_t fd_buffer_bytes(int fd) {
  int value = 0;
  socklen_t size = sizeof value;
  if (::getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &value, &size) != 0) return -1;
  return value / 2;  // Linux reports twice what was set (see SocketBuffer)
}

std::string slurp(const char* path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

uint64_t socket_inode(int fd) {
  struct stat st {};
  if (fd < 0 || ::fstat(fd, &st) != 0 || !S_ISSOCK(st.st_mode)) return 0;
  return static_cast<uint64_t>(st.st_ino);
}

std::optional<uint64_t> drops_of_inode(uint64_t inode) {
  if (inode == 0) return std::nullopt;
  for (const char* path : {"/proc/net/udp", "/proc/net/udp6"})
    if (const auto d = udp_drops_in(slurp(path), inode)) return d;
  return std::nullopt;
}

}  // namespace

std::string socket_buffer_text(const SocketBuffer& b) {
  std::string t = b.asked_bytes > 0 ? "asked " + bytes(b.asked_bytes)
                                    : std::string("the system's default (net.core.rmem_default)");
  t += b.got_bytes >= 0 ? ", got " + bytes(b.got_bytes) : std::string(", not measured");
  t += b.rmem_max_bytes >= 0 ? " (net.core.rmem_max " + bytes(b.rmem_max_bytes) + ")"
                             : std::string(" (net.core.rmem_max unreadable)");
  if (b.short_of_asked())
    t += ": LESS than asked (forcing it, SO_RCVBUFFORCE, needs root or CAP_NET_ADMIN), so a busy "
         "machine may drop packets: run the station as root or raise the limit with `sysctl -w "
         "net.core.rmem_max=" +
         std::to_string(b.asked_bytes) + "`";
  return t;
}

int64_t read_rmem_max() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  int64_t v = -1;
  return in >> v ? v : -1;
}

SocketBuffer probe_socket_buffer(int64_t asked) {
  SocketBuffer b;
  b.asked_bytes = asked;
  b.rmem_max_bytes = read_rmem_max();
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return b;
  if (asked > 0) {
    const int want = static_cast<int>(std::min<int64_t>(asked, INT_MAX));
    // udpsrc's order: the plain option, which the kernel caps at rmem_max; forced (privileged)
    // when that failed or gave less.
    const bool failed = ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &want, sizeof want) != 0;
    if (failed || fd_buffer_bytes(fd) < asked)
      (void)::setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &want, sizeof want);
  }
  b.got_bytes = fd_buffer_bytes(fd);
  ::close(fd);
  return b;
}

int64_t socket_buffer_bytes(GSocket* socket) {
  gint value = 0;
  if (socket == nullptr || !g_socket_get_option(socket, SOL_SOCKET, SO_RCVBUF, &value, nullptr))
    return -1;
  return value / 2;
}

// Lines of "sl local rem st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops".
std::optional<uint64_t> udp_drops_in(std::string_view text, uint64_t inode) {
  std::istringstream lines{std::string(text)};
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::vector<std::string> f;
    for (std::string w; in >> w;) f.push_back(w);
    if (f.size() < 13) continue;
    try {
      if (std::stoull(f[9]) == inode) return std::stoull(f[12]);
    } catch (const std::exception&) {  // not a socket's line
    }
  }
  return std::nullopt;
}

std::optional<uint64_t> udp_socket_drops(int fd) {
  return drops_of_inode(socket_inode(fd));
}

ReceiveSocketWatch::ReceiveSocketWatch(int64_t rtp_asked_bytes, int64_t rtcp_asked_bytes) {
  report_.rtp.asked_bytes = rtp_asked_bytes;
  report_.rtcp.asked_bytes = rtcp_asked_bytes;
}

void ReceiveSocketWatch::measure(GSocket* rtp, GSocket* rtcp) {
  auto open = [](GSocket* s) { return s != nullptr && !g_socket_is_closed(s); };
  const int64_t rmem_max = read_rmem_max();
  const int64_t rtp_got = open(rtp) ? socket_buffer_bytes(rtp) : -1;
  const int64_t rtcp_got = open(rtcp) ? socket_buffer_bytes(rtcp) : -1;
  const uint64_t inode = open(rtp) ? socket_inode(g_socket_get_fd(rtp)) : 0;
  const std::optional<uint64_t> drops = drops_of_inode(inode);
  std::lock_guard lock(mutex_);
  if (rtp_got >= 0) report_.rtp = {report_.rtp.asked_bytes, rtp_got, rmem_max};
  if (rtcp_got >= 0) report_.rtcp = {report_.rtcp.asked_bytes, rtcp_got, rmem_max};
  if (!drops) return;
  if (inode != inode_) {  // a new socket (the pipeline was rebuilt): its count starts at 0
    drops_closed_ += drops_open_;
    inode_ = inode;
  }
  drops_open_ = *drops;
  report_.kernel_drops = static_cast<int64_t>(drops_closed_ + drops_open_);
}

ReceiveSocketWatch::Report ReceiveSocketWatch::report() const {
  std::lock_guard lock(mutex_);
  return report_;
}

}  // namespace hd::drivers
