// Cost of validating + decoding one head tracker report per format, beside its peer: copying
// the same bytes (the floor any parser pays), and the device clock mapping step.
#include <benchmark/benchmark.h>

#include <cstring>
#include <vector>

#include "drivers/clock/device_clock_mapper.h"
#include "drivers/hid/hid_report_encoder.h"
#include "drivers/hid/hid_report_parser.h"

namespace {

using namespace hd::drivers;

std::vector<uint8_t> report_for(const HidReportFormat& f) {
  HidSample s;
  s.q_tracker_head = Eigen::Quaterniond(0.9, 0.1, -0.3, 0.2).normalized();
  s.angular_velocity_rad_s = {0.5, -1.0, 2.0};
  std::vector<uint8_t> r(64);
  r.resize(encode_hid_report(f, s, r));
  return r;
}

void BM_Parse(benchmark::State& state, HidReportFormat f) {
  const std::vector<uint8_t> r = report_for(f);
  for (auto _ : state) {
    const HidParseResult res = parse_hid_report(f, r);
    benchmark::DoNotOptimize(res);
  }
}
BENCHMARK_CAPTURE(BM_Parse, android, android_head_tracker_v1());
BENCHMARK_CAPTURE(BM_Parse, osvr, osvr_hdk());

void BM_PeerCopyReport(benchmark::State& state) {
  const std::vector<uint8_t> r = report_for(android_head_tracker_v1());
  uint8_t out[64];
  for (auto _ : state) {
    benchmark::DoNotOptimize(r.data());
    std::memcpy(out, r.data(), r.size());
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_PeerCopyReport);

void BM_ClockMap(benchmark::State& state) {
  DeviceClockMapper m;
  uint64_t dev = 0;
  int64_t host = 1'000'000'000;
  for (auto _ : state) {
    dev += 1000;
    host += 1'000'000 + static_cast<int64_t>(dev % 7919);
    benchmark::DoNotOptimize(m.map(dev, host));
  }
}
BENCHMARK(BM_ClockMap);

}  // namespace
