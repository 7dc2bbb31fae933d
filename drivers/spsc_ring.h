#pragma once
// Every sample, in order, from one device thread to one consumer (pose history for prediction).

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace hd::drivers {

/// Bounded lock-free single-producer / single-consumer queue of trivially copyable values.
/// When full, push() drops the new value and counts it (the consumer fell behind); it never blocks.
template <class T, std::size_t N>
class SpscRing {
  static_assert((N & (N - 1)) == 0, "N must be a power of two");

 public:
  bool push(const T& v) {
    const uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= N) {
      overflow_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    items_[head & (N - 1)] = v;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  bool pop(T& out) {
    const uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    out = items_[tail & (N - 1)];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  uint64_t overflowed() const { return overflow_.load(std::memory_order_relaxed); }

 private:
  std::array<T, N> items_{};
  alignas(64) std::atomic<uint64_t> head_{0};
  alignas(64) std::atomic<uint64_t> tail_{0};
  std::atomic<uint64_t> overflow_{0};
};

}  // namespace hd::drivers
