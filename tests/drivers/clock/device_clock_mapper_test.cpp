// DeviceClockMapper against synthetic device clocks whose true event times are known: the mapped
// time must land on (true event time + the smallest one-way delay) within the counter's tick.
#include "drivers/clock/device_clock_mapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "drivers/clock/monotonic_clock.h"

namespace hd::drivers {
namespace {

struct SyntheticDevice {
  int counter_bits = 32;
  double tick_ns = 1000.0;
  double skew_ppm = 0.0;         // device clock rate error
  double device_start_ns = 0.0;  // device clock reading at host time 0
  int64_t base_delay_ns = 300'000;
  int64_t jitter_ns = 2'000'000;  // uniform extra delay [0, jitter]

  uint64_t counter_at(int64_t host_event_ns) const {
    const double dev_ns =
        device_start_ns + static_cast<double>(host_event_ns) * (1.0 + skew_ppm * 1e-6);
    const auto ticks = static_cast<uint64_t>(std::floor(dev_ns / tick_ns));
    return counter_bits == 64 ? ticks : (ticks & ((uint64_t{1} << counter_bits) - 1));
  }
};

// Runs `n` samples at `period_ns` and returns the worst |mapped - (event + base_delay)| after
// `warmup` samples; checks the two guarantees (not after arrival, never backwards) on every one.
int64_t run(const SyntheticDevice& dev, DeviceClockMapper& mapper, int n, int64_t period_ns,
            int warmup, std::mt19937_64& rng, int64_t t0_ns = 1'000'000'000) {
  std::uniform_int_distribution<int64_t> jitter(0, dev.jitter_ns);
  int64_t worst = 0;
  int64_t prev = INT64_MIN;
  int64_t prev_arrival_ns = INT64_MIN;
  for (int k = 0; k < n; ++k) {
    const int64_t event_ns = t0_ns + k * period_ns;
    // One link delivers in order (FIFO): a report cannot overtake the one before it.
    const int64_t arrival_ns =
        std::max(prev_arrival_ns, event_ns + dev.base_delay_ns + jitter(rng));
    prev_arrival_ns = arrival_ns;
    const int64_t mapped = mapper.map(dev.counter_at(event_ns), arrival_ns);
    EXPECT_LE(mapped, arrival_ns) << "sample " << k;
    EXPECT_GE(mapped, prev) << "sample " << k;
    prev = mapped;
    const int64_t err = mapped - (event_ns + dev.base_delay_ns);
    if (k >= warmup) worst = std::max(worst, err < 0 ? -err : err);
  }
  return worst;
}

TEST(DeviceClockMapper, MicrosecondCounterWithJitterConvergesToMinimumDelay) {
  SyntheticDevice dev;
  DeviceClockMapper mapper({.counter_bits = 32, .tick_ns = 1000.0});
  std::mt19937_64 rng(1);
  // 1 kHz for 5 s, jitter up to 2 ms: after 1 s the minimum has seen near-zero jitter.
  const int64_t worst = run(dev, mapper, 5000, 1'000'000, 1000, rng);
  // The estimate rises by 200 ppm between near-minimum-delay samples (~1 in 100 arrives within
  // 20 us of the minimum), so it sits within ~0.1 ms of the minimum delay, against 2 ms of jitter.
  EXPECT_LT(worst, 100'000);
  // Residual = arrival - mapped ~ uniform jitter on [0, 2 ms] plus the tiny bias: mean ~1 ms,
  // stddev ~ 2 ms / sqrt(12) = 0.577 ms.
  EXPECT_NEAR(mapper.residual_mean_ns(), 1.0e6, 0.1e6);
  EXPECT_NEAR(mapper.residual_stddev_ns(), 2.0e6 / std::sqrt(12.0), 0.06e6);
  EXPECT_EQ(mapper.resets(), 0u);
}

TEST(DeviceClockMapper, UnwrapsSixteenBitMillisecondCounterOverManyRollovers) {
  SyntheticDevice dev{.counter_bits = 16, .tick_ns = 1e6, .device_start_ns = 65'000e6};
  DeviceClockMapper mapper({.counter_bits = 16, .tick_ns = 1e6});
  std::mt19937_64 rng(2);
  // 200 s at 100 Hz: the 65.536 s counter wraps three times (the first after 0.5 s).
  const int64_t worst = run(dev, mapper, 20'000, 10'000'000, 500, rng);
  EXPECT_LT(worst, 1'100'000);  // one 1 ms tick of quantisation plus a little
  EXPECT_EQ(mapper.resets(), 0u);
  EXPECT_NEAR(static_cast<double>(mapper.last_device_ns()), 19'999 * 10e6, 2e6);
}

TEST(DeviceClockMapper, SilenceLongerThanOneCounterPeriodStillUnwraps) {
  SyntheticDevice dev{.counter_bits = 16, .tick_ns = 1e6, .jitter_ns = 0};
  DeviceClockMapper mapper({.counter_bits = 16, .tick_ns = 1e6});
  std::mt19937_64 rng(3);
  run(dev, mapper, 100, 10'000'000, 0, rng);
  // Device silent for 150 s (2.3 counter periods), then one sample.
  const int64_t event_ns = 1'000'000'000 + 99 * 10'000'000 + 150'000'000'000;
  const int64_t mapped = mapper.map(dev.counter_at(event_ns), event_ns + dev.base_delay_ns);
  EXPECT_NEAR(static_cast<double>(mapped), static_cast<double>(event_ns + dev.base_delay_ns), 2e6);
  EXPECT_EQ(mapper.resets(), 0u);
}

class DeviceClockMapperDrift : public ::testing::TestWithParam<double> {};

TEST_P(DeviceClockMapperDrift, FollowsSlowAndFastDeviceClocks) {
  SyntheticDevice dev{.skew_ppm = GetParam()};
  DeviceClockMapper mapper({.counter_bits = 32, .tick_ns = 1000.0, .max_drift_ppm = 200.0});
  std::mt19937_64 rng(4);
  // 20 s at 500 Hz: uncorrected, 100 ppm would add 2 ms of error by the end.
  const int64_t worst = run(dev, mapper, 10'000, 2'000'000, 1000, rng);
  EXPECT_LT(worst, 150'000);
}

INSTANTIATE_TEST_SUITE_P(Skews, DeviceClockMapperDrift, ::testing::Values(-100.0, 0.0, 100.0));

TEST(DeviceClockMapper, DeviceResetIsDetectedAndRelearned) {
  SyntheticDevice dev{.device_start_ns = 5e12};
  DeviceClockMapper mapper;
  std::mt19937_64 rng(5);
  constexpr int64_t kT0 = 1'000'000'000;
  constexpr int64_t kPeriod = 1'000'000;
  run(dev, mapper, 2000, kPeriod, 0, rng, kT0);
  // The device reboots: its counter restarts at zero at the next sample.
  constexpr int64_t kRebootAt = kT0 + 2000 * kPeriod;
  SyntheticDevice rebooted = dev;
  rebooted.device_start_ns = -static_cast<double>(kRebootAt);
  const int64_t worst = run(rebooted, mapper, 3000, kPeriod, 1000, rng, kRebootAt);
  EXPECT_EQ(mapper.resets(), 1u);
  EXPECT_LT(worst, 100'000);
}

TEST(DeviceClockMapper, DeviceTimeGoingBackwardsNeverMovesMappedTimeBackwards) {
  DeviceClockMapper mapper({.counter_bits = 32, .tick_ns = 1000.0});
  const int64_t a = mapper.map(10'000, 1'000'000'000);
  const int64_t b = mapper.map(10'500, 1'000'600'000);
  const int64_t c = mapper.map(10'400, 1'000'700'000);  // reordered by 100 us: not a reset
  // 500 us of device time; the offset may rise by at most 200 ppm of the 600 us host gap.
  EXPECT_GE(b - a, 500'000);
  EXPECT_LE(b - a, 500'000 + 120);
  EXPECT_GE(c, b);
  EXPECT_EQ(mapper.last_device_ns(), 400'000);
  EXPECT_EQ(mapper.resets(), 0u);
}

TEST(MonotonicClock, IsMonotonicAndNanoseconds) {
  const int64_t a = monotonic_now_ns();
  const int64_t b = monotonic_now_ns();
  EXPECT_GE(b, a);
  EXPECT_GT(a, 0);
}

}  // namespace
}  // namespace hd::drivers
