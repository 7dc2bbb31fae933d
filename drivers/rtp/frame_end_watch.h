#pragma once
// Notices a frame whose last packet did not come, and says which sequence number to ask for.
//
// Why: the jitter buffer finds a loss from the gap the next packet leaves. A frame's packets come
// as one burst and the next burst is the next frame, a frame period (33 ms at 30 Hz) later: a lost
// last packet is noticed only then, past a 20 ms jitter buffer's deadline, and the frame (and the
// frames up to the next key frame, which reference it) is lost although a retransmission would
// have come in a millisecond. The RTP marker bit marks a frame's last packet (RFC 6184 5.1): when
// the newest packet is not one, and nothing newer comes within wait_ns, the packet after it is due
// now and is asked for. Its repair may itself be lost: asked again every retry_ns, at most
// max_requests times, until a newer packet comes. A retransmission of the asked packet counts as
// the packet (its marker bit is the original's, RFC 4588 4).
//
// Pure: the caller passes arrival and current times (CLOCK_MONOTONIC ns) and arms one timer at
// due_ns(); not thread-safe (the camera locks it).
#include <cstdint>
#include <optional>

namespace hd::drivers {

class FrameEndWatch {
 public:
  struct Settings {
    /// Packets of a burst come microseconds apart on a LAN; 3 ms is past any burst's gap on a
    /// busy station yet a tenth of a frame period. A wait that fires inside a burst costs one
    /// duplicate packet (counted as a retransmission), never a frame.
    int64_t wait_ns = 3'000'000;
    int64_t retry_ns = 10'000'000;  ///< again if the repair did not come: a LAN round trip x ~10
    int max_requests = 3;
  };

  explicit FrameEndWatch(Settings s) : s_(s) {}

  /// How long after the newest packet its frame's end is due from now on (the link's reorder).
  void set_wait(int64_t wait_ns) { s_.wait_ns = wait_ns; }
  /// A media packet (or the repair of one) of the stream, in arrival order.
  void on_packet(uint16_t sequence, bool marker, int64_t arrival_ns);
  /// When the frame end is due (0: nothing awaited).
  int64_t due_ns() const { return due_ns_; }
  /// At or after due_ns(): the sequence number to ask for now, and the next due time set.
  std::optional<uint16_t> on_due(int64_t now_ns);
  uint64_t requests() const { return requests_; }

 private:
  Settings s_;
  bool started_ = false;
  uint16_t highest_ = 0;
  int64_t due_ns_ = 0;
  int tries_ = 0;
  uint64_t requests_ = 0;
};

}  // namespace hd::drivers
