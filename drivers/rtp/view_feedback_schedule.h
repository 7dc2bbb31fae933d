#pragma once
// When the station tells a camera's sender whether it needs the camera at full rate (the HDBW
// RTCP APP message of view_feedback.h), and the message itself: the decision with the time
// passed in, so that it needs no network.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "drivers/rtp/view_feedback.h"

namespace hd::drivers {

/// A change goes out at once (at the caller's next turn), the same need again every kRepeatNs:
/// the sender falls back to full rate after 2 s without any, so silence is never "not needed".
/// Nothing is due before set_needed() was ever called (the sender stays at full rate) or before
/// the sender's address is known (set_target(): where its RTCP comes from).
///
/// Threads: set_needed() from the frame loop (one atomic store, lock-free); set_target() from the
/// RTCP source's streaming thread; due() and take() from one sending thread (the bus thread).
class ViewFeedbackSchedule {
 public:
  static constexpr int64_t kRepeatNs = 500'000'000;

  /// One message to send: the datagram (`size` bytes of `bytes`) and where to.
  struct Message {
    std::string host;
    int port = 0;
    std::array<uint8_t, kAuthenticatedViewFeedbackSize> bytes{};
    std::size_t size = 0;
  };

  /// With `key` (from the stream's SRTP key) every message carries its tag (version 2).
  explicit ViewFeedbackSchedule(std::optional<ViewFeedbackKey> key = std::nullopt);

  void set_needed(bool needed) { need_.store(needed ? 1 : 0, std::memory_order_relaxed); }
  /// What set_needed said last (true before: full rate).
  bool needed() const { return need_.load(std::memory_order_relaxed) != 0; }
  /// The sender's RTCP address (a new sender, or the first): it hears the need at once.
  void set_target(const std::string& host, int port);

  /// Whether a message is due at `now_ns` (CLOCK_MONOTONIC).
  bool due(int64_t now_ns) const;
  /// The message due now, with the next sequence number; from here the next is due kRepeatNs
  /// after `now_ns`, or at a change. Call after due() said so.
  Message take(int64_t now_ns);
  /// The message went out whole.
  void count_sent() { sent_.fetch_add(1, std::memory_order_relaxed); }
  uint64_t sent() const { return sent_.load(std::memory_order_relaxed); }

 private:
  std::optional<ViewFeedbackKey> key_;
  std::atomic<int> need_{-1};  // -1: never set
  mutable std::mutex mutex_;   // the target and what was sent when
  std::string host_;
  int port_ = 0;
  int sent_need_ = -1;
  int64_t sent_ns_ = 0;  // 0: due at the next turn (nothing sent, or a new target)
  uint16_t sequence_ = 0;
  std::atomic<uint64_t> sent_{0};
};

}  // namespace hd::drivers
