#pragma once
// The simulation's one clock origin, shared by its devices: the first device to start claims it,
// so camera exposures, head samples and moving objects all use the same scene time.

#include <atomic>
#include <cstdint>

namespace hd::sim {

class SimEpoch {
 public:
  /// The epoch; the first caller sets it to `now_ns`.
  int64_t claim(int64_t now_ns) {
    int64_t expected = 0;
    if (epoch_ns_.compare_exchange_strong(expected, now_ns, std::memory_order_acq_rel)) {
      return now_ns;
    }
    return expected;
  }
  int64_t get() const { return epoch_ns_.load(std::memory_order_acquire); }

 private:
  std::atomic<int64_t> epoch_ns_{0};
};

}  // namespace hd::sim
