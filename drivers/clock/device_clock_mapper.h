#pragma once
// Maps a device's own timestamps (a counter of some bit width that rolls over) onto host
// CLOCK_MONOTONIC nanoseconds.
//
// Why the running minimum: every arrival is the device event plus a one-way delay that is never
// negative (USB polling, scheduling). The smallest (host_arrival - device_time) seen so far is
// therefore the best estimate of the clock offset plus the fixed part of the delay; everything
// above it is jitter. To follow a device clock that runs slow (its offset grows), the minimum is
// allowed to rise by at most `max_drift_ppm` of the elapsed host time before each new sample.

#include <cstdint>

namespace hd::drivers {

struct DeviceClockMapperConfig {
  int counter_bits = 32;         ///< width of the device counter before it rolls over
  double tick_ns = 1000.0;       ///< one device tick in nanoseconds (1000 = microseconds)
  double max_drift_ppm = 200.0;  ///< how fast the offset estimate may rise (slow device)
  int64_t reset_threshold_ns = 100'000'000;  ///< device vs host disagreement that means a reset
};

class DeviceClockMapper {
 public:
  explicit DeviceClockMapper(DeviceClockMapperConfig config = {});

  /// Maps one device timestamp (raw counter value, only the low `counter_bits` are used) that
  /// arrived at `host_arrival_ns`. The result is never later than the arrival and never earlier
  /// than the previous result.
  int64_t map(uint64_t device_counter, int64_t host_arrival_ns);

  /// The device clock on its own unwrapped timeline (ns since the first sample after a reset).
  int64_t last_device_ns() const { return last_device_ns_; }
  /// Current estimate of host - device (ns).
  int64_t offset_ns() const { return offset_ns_; }
  /// Times the device counter jumped in a way host time does not explain (device reboot).
  uint64_t resets() const { return resets_; }
  uint64_t samples() const { return samples_; }

  /// Residual = arrival - mapped time: the measured delay above the minimum (>= 0).
  double residual_mean_ns() const;
  double residual_stddev_ns() const;
  int64_t residual_max_ns() const { return residual_max_ns_; }

 private:
  void restart(int64_t host_arrival_ns);

  DeviceClockMapperConfig config_;
  uint64_t counter_mask_;
  bool started_ = false;
  uint64_t last_counter_ = 0;
  int64_t last_device_ns_ = 0;
  int64_t last_host_ns_ = 0;
  int64_t offset_ns_ = 0;
  int64_t last_mapped_ns_ = INT64_MIN;
  uint64_t resets_ = 0;
  uint64_t samples_ = 0;
  // Welford running mean/variance of the residual.
  uint64_t residual_n_ = 0;
  double residual_mean_ = 0.0;
  double residual_m2_ = 0.0;
  int64_t residual_max_ns_ = 0;
};

}  // namespace hd::drivers
