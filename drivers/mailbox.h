#pragma once
// Latest-value hand-off from one device thread to the render loop.

#include <array>
#include <atomic>
#include <cstdint>

namespace hd::drivers {

/// Lock-free single-producer / single-consumer "newest value wins" mailbox (a triple buffer).
///
/// The producer fills `write_slot()` in place and calls `publish()`; the consumer calls `fetch()`
/// and then reads `latest()`, which stays untouched by the producer until the next `fetch()`.
/// Neither side locks, waits or allocates: all three slots are constructed up front, so a `T`
/// whose buffers are sized at construction (a `Frame`) is never reallocated on the per-frame path.
/// Values the consumer never fetched are overwritten; `published()` lets it count them.
template <class T>
class Mailbox {
 public:
  Mailbox() = default;
  explicit Mailbox(const T& prototype) : slots_{prototype, prototype, prototype} {}
  Mailbox(const Mailbox&) = delete;
  Mailbox& operator=(const Mailbox&) = delete;

  /// Producer: the slot to fill. Only valid until the next publish().
  T& write_slot() { return slots_[back_]; }

  /// Producer: make the filled slot the newest value.
  void publish() {
    back_ =
        state_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel) & kIndex;
    published_.fetch_add(1, std::memory_order_relaxed);
  }

  /// Consumer: take the newest value if one arrived since the last fetch. Returns false (and keeps
  /// `latest()` as it was) when nothing new was published.
  bool fetch() {
    if ((state_.load(std::memory_order_acquire) & kFresh) == 0) return false;
    front_ = state_.exchange(front_, std::memory_order_acq_rel) & kIndex;
    return true;
  }

  /// Producer: true when the consumer has fetched the last published value (or nothing was
  /// published yet). Lets a source that must not lose values (a replayed recording) wait for the
  /// consumer instead of overwriting.
  bool taken() const { return (state_.load(std::memory_order_acquire) & kFresh) == 0; }

  /// Consumer: the value taken by the last successful fetch().
  const T& latest() const { return slots_[front_]; }
  T& latest_mut() { return slots_[front_]; }

  /// Count of publish() calls so far (any thread).
  uint64_t published() const { return published_.load(std::memory_order_relaxed); }

 private:
  static constexpr uint8_t kIndex = 0x3;
  static constexpr uint8_t kFresh = 0x4;
  std::array<T, 3> slots_{};
  uint8_t back_ = 0;               // producer-owned
  uint8_t front_ = 1;              // consumer-owned
  std::atomic<uint8_t> state_{2};  // middle slot index | fresh flag
  std::atomic<uint64_t> published_{0};
};

}  // namespace hd::drivers
