#include "drivers/clock/device_clock_mapper.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace hd::drivers {

DeviceClockMapper::DeviceClockMapper(DeviceClockMapperConfig config) : config_(config) {
  config_.counter_bits = std::clamp(config_.counter_bits, 1, 64);
  counter_mask_ =
      config_.counter_bits == 64 ? ~uint64_t{0} : ((uint64_t{1} << config_.counter_bits) - 1);
  if (!(config_.tick_ns > 0.0) || !std::isfinite(config_.tick_ns)) config_.tick_ns = 1.0;
}

void DeviceClockMapper::restart(int64_t host_arrival_ns) {
  // The device timeline restarts at 0 for this sample; the offset is re-learned from here.
  last_device_ns_ = 0;
  last_host_ns_ = host_arrival_ns;
  offset_ns_ = host_arrival_ns;
}

int64_t DeviceClockMapper::map(uint64_t device_counter, int64_t host_arrival_ns) {
  device_counter &= counter_mask_;
  ++samples_;
  if (!started_) {
    started_ = true;
    last_counter_ = device_counter;
    restart(host_arrival_ns);
  } else {
    const int64_t host_elapsed_ns = host_arrival_ns - last_host_ns_;
    const uint64_t delta_mod = (device_counter - last_counter_) & counter_mask_;
    // Choose how many whole rollovers happened from host time, so a device silent for longer
    // than one counter period still unwraps correctly.
    const double range_ticks = std::ldexp(1.0, config_.counter_bits);
    const double expected_ticks = static_cast<double>(host_elapsed_ns) / config_.tick_ns;
    // wraps = -1 is a small step backwards (a reordered or re-sent sample), not a rollover.
    const double wraps =
        std::round((expected_ticks - static_cast<double>(delta_mod)) / range_ticks);
    const double device_advance_ns =
        (static_cast<double>(delta_mod) + wraps * range_ticks) * config_.tick_ns;
    const double disagreement_ns = device_advance_ns - static_cast<double>(host_elapsed_ns);
    const double allowed_ns = static_cast<double>(config_.reset_threshold_ns) +
                              config_.max_drift_ppm * 1e-6 * static_cast<double>(host_elapsed_ns);
    last_counter_ = device_counter;
    if (std::fabs(disagreement_ns) > allowed_ns) {
      ++resets_;
      restart(host_arrival_ns);
    } else {
      last_device_ns_ += static_cast<int64_t>(std::llround(device_advance_ns));
      // Let the minimum rise slowly so a slow device clock is followed, then take the minimum.
      const int64_t leak_ns =
          static_cast<int64_t>(config_.max_drift_ppm * 1e-6 *
                               static_cast<double>(std::max<int64_t>(host_elapsed_ns, 0)));
      offset_ns_ = std::min(offset_ns_ + leak_ns, host_arrival_ns - last_device_ns_);
      last_host_ns_ = host_arrival_ns;
    }
  }
  int64_t mapped_ns = last_device_ns_ + offset_ns_;
  if (mapped_ns < last_mapped_ns_) mapped_ns = last_mapped_ns_;  // forward progress
  last_mapped_ns_ = mapped_ns;

  const int64_t residual_ns = host_arrival_ns - mapped_ns;
  ++residual_n_;
  const double r = static_cast<double>(residual_ns);
  const double d = r - residual_mean_;
  residual_mean_ += d / static_cast<double>(residual_n_);
  residual_m2_ += d * (r - residual_mean_);
  residual_max_ns_ = std::max(residual_max_ns_, residual_ns);
  return mapped_ns;
}

double DeviceClockMapper::residual_mean_ns() const {
  return residual_mean_;
}

double DeviceClockMapper::residual_stddev_ns() const {
  return residual_n_ > 1 ? std::sqrt(residual_m2_ / static_cast<double>(residual_n_ - 1)) : 0.0;
}

}  // namespace hd::drivers
