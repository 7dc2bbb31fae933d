#pragma once
// The network camera's receive sockets: their kernel buffers as asked (udpsrc buffer-size) and as
// given, the system's limit, and the datagrams the kernel dropped on a socket because its buffer
// was full (udpsrc's thread did not read in time: a busy machine).

#include <gio/gio.h>

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace hd::drivers {

/// One socket's receive buffer, bytes. Linux reports (SO_RCVBUF) twice what was set: the other
/// half is its allowance for bookkeeping (each datagram is charged its whole skb, about 2.3 KB for
/// a 1.4 KB RTP packet on loopback). `got_bytes` is the halved figure, as udpsrc compares it.
struct SocketBuffer {
  int64_t asked_bytes = 0;      ///< 0: the system's default (net.core.rmem_default)
  int64_t got_bytes = -1;       ///< -1: not measured (no socket yet)
  int64_t rmem_max_bytes = -1;  ///< net.core.rmem_max, the most without privilege; -1 unreadable
  bool short_of_asked() const {
    return asked_bytes > 0 && got_bytes >= 0 && got_bytes < asked_bytes;
  }
};

/// "asked 2097152 B, got 2097152 B (net.core.rmem_max 4194304 B)". When it got less than asked,
/// what to do: "...: LESS than asked (forcing it, SO_RCVBUFFORCE, needs root or CAP_NET_ADMIN):
/// a busy machine may drop packets; run the station as root or raise the limit with `sysctl -w
/// net.core.rmem_max=2097152`".
std::string socket_buffer_text(const SocketBuffer& b);

/// net.core.rmem_max (/proc/sys/net/core/rmem_max); -1 when unreadable.
int64_t read_rmem_max();

/// What this process gets for a UDP socket's receive buffer of `asked` bytes, set as GStreamer
/// 1.22's udpsrc sets it (SO_RCVBUF, then SO_RCVBUFFORCE when that gave less): measured on a
/// socket of its own, for the start report before the pipeline's sockets exist. asked 0: the
/// default, untouched.
SocketBuffer probe_socket_buffer(int64_t asked);

/// `socket`'s receive buffer as the kernel gave it (SO_RCVBUF, halved); -1 when unreadable.
int64_t socket_buffer_bytes(GSocket* socket);

/// The `drops` column of /proc/net/udp or /proc/net/udp6 text for the socket whose inode is
/// `inode`; none when no line has it.
std::optional<uint64_t> udp_drops_in(std::string_view proc_net_udp, uint64_t inode);
/// The kernel's drop count of UDP socket `fd` (found by its inode in /proc/net/udp and udp6).
std::optional<uint64_t> udp_socket_drops(int fd);

/// One camera's receive sockets as last measured, and the kernel's drops on its RTP socket summed
/// over the pipeline's rebuilds (each opens new sockets, whose counts start at 0; drops in the
/// moments between the last measure() and a socket's close are not seen). Any thread but the
/// render thread: it takes a mutex and reads /proc.
class ReceiveSocketWatch {
 public:
  struct Report {
    SocketBuffer rtp, rtcp;
    int64_t kernel_drops = -1;  ///< datagrams dropped on the RTP socket; -1 never measured
  };
  ReceiveSocketWatch(int64_t rtp_asked_bytes, int64_t rtcp_asked_bytes);
  /// Reads the open sockets now (null or closed: the last figures stay).
  void measure(GSocket* rtp, GSocket* rtcp);
  Report report() const;

 private:
  mutable std::mutex mutex_;
  Report report_;
  uint64_t inode_ = 0;         // the RTP socket measured last
  uint64_t drops_closed_ = 0;  // on its predecessors
  uint64_t drops_open_ = 0;    // on it
};

}  // namespace hd::drivers
