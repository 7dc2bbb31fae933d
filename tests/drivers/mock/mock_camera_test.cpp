#include "drivers/mock/mock_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <vector>

#include "drivers/clock/monotonic_clock.h"

#include "test_wait.h"

namespace hd::drivers {
namespace {

TEST(MockCamera, TestPatternCarriesSequenceAndGradient) {
  Frame f;
  f.allocate_rgba(32, 16);
  write_test_pattern(f, 0x0102030405060708ull);
  EXPECT_EQ(read_test_pattern_sequence(f), 0x0102030405060708ull);
  const uint8_t* p = f.data.data() + 5 * f.stride_bytes + 4 * 10;  // x = 10, y = 5
  EXPECT_EQ(p[0], 10 * 255 / 31);
  EXPECT_EQ(p[1], 5 * 255 / 15);
  EXPECT_EQ(p[3], 255);
  Frame tiny;
  EXPECT_EQ(read_test_pattern_sequence(tiny), UINT64_MAX);
}

TEST(MockCamera, ServesFramesWithScriptedDropsAndClockOffset) {
  MockCamera cam({.width = 16,
                  .height = 8,
                  .rate_hz = 250.0,
                  .device_clock_offset_ns = 5'000'000'000,
                  .drop_sequences = {3, 5}});
  cam.start();
  std::vector<uint64_t> seen;
  ASSERT_TRUE(eventually([&] {
    if (cam.frames().fetch()) {
      const Frame& f = cam.frames().latest();
      EXPECT_EQ(read_test_pattern_sequence(f), f.sequence);
      EXPECT_EQ(f.device_timestamp_ns - f.host_timestamp_ns, 5'000'000'000);
      EXPECT_EQ(f.width, 16);
      seen.push_back(f.sequence);
    }
    return !seen.empty() && seen.back() >= 12;
  }));
  cam.stop();
  // A loaded machine may make the camera thread miss a slot: that is an overrun, counted apart.
  EXPECT_EQ(cam.dropped_frames(), 2u + cam.overrun_frames());
  for (uint64_t s : seen) EXPECT_TRUE(s != 3 && s != 5) << s;
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GT(seen[i], seen[i - 1]);
}

TEST(MockCamera, ScriptedStallIsReportedAndRecovers) {
  MockCamera cam({.rate_hz = 200.0,
                  .stalls = {{.before_sequence = 4, .duration_ns = 600'000'000}},
                  .stall_timeout_ns = 100'000'000});
  cam.start();
  ASSERT_TRUE(eventually([&] { return cam.state() == SourceState::kStalled; }));
  ASSERT_TRUE(eventually([&] { return cam.state() == SourceState::kStreaming; }));
  cam.stop();
  EXPECT_EQ(cam.state(), SourceState::kClosed);
  EXPECT_EQ(cam.dropped_frames(), cam.overrun_frames());  // the stall itself loses nothing
}

// What the newest frame's age grows to while a generator takes three periods per frame.
struct SlowRun {
  int64_t worst_age_ns = 0;
  std::vector<uint64_t> seen;
  std::vector<int64_t> age_ns;  ///< each fetched frame's age when fetched
  uint64_t dropped = 0, overruns = 0;
  /// How much older the last 10 fetched frames were than the first 10 (mean against mean): a
  /// camera that keeps its clock does not fall behind, so this stays near 0 whatever the load;
  /// one that delivers every frame late falls ~10 ms further behind per frame.
  double growth_ms() const {
    double first = 0, last = 0;
    for (int i = 0; i < 10; ++i) {
      first += static_cast<double>(age_ns[static_cast<std::size_t>(i)]);
      last += static_cast<double>(age_ns[age_ns.size() - 10 + static_cast<std::size_t>(i)]);
    }
    return (last - first) / 10 * 1e-6;
  }
};
SlowRun run_slow_camera(bool drop_on_overrun) {
  MockCamera cam({.rate_hz = 200.0,
                  .generator =
                      [](Frame& f, uint64_t s) {
                        std::this_thread::sleep_for(std::chrono::milliseconds(15));
                        write_test_pattern(f, s);
                      },
                  .drop_on_overrun = drop_on_overrun});
  cam.start();
  SlowRun r;
  eventually([&] {
    if (cam.frames().fetch()) {
      const Frame& f = cam.frames().latest();
      r.age_ns.push_back(monotonic_now_ns() - f.host_timestamp_ns);
      r.worst_age_ns = std::max(r.worst_age_ns, r.age_ns.back());
      r.seen.push_back(f.sequence);
    }
    return r.seen.size() >= 40;
  });
  cam.stop();
  r.dropped = cam.dropped_frames();
  r.overruns = cam.overrun_frames();
  return r;
}

TEST(MockCamera, SlowGeneratorLosesFramesInsteadOfDeliveringThemLate) {
  // 5 ms period, 15 ms to make a frame: like a sensor that keeps its clock, about two frames in
  // three are lost and what arrives does not fall behind. Asserted as the age's growth over the
  // run, not as a bound on the age itself: that was a wall-clock bound (150 ms against ~20 ms
  // idle) which a thread kept off the CPU long enough would break.
  const SlowRun r = run_slow_camera(true);
  ASSERT_EQ(r.seen.size(), 40u);
  EXPECT_GT(r.overruns, 0u);
  EXPECT_EQ(r.dropped, r.overruns);
  EXPECT_GE(r.seen.back(), 2 * r.seen.size()) << "sequence gaps: the lost frames";
  EXPECT_LT(r.growth_ms(), 100.0) << "the last frames were older than the first";
  for (std::size_t i = 1; i < r.seen.size(); ++i) EXPECT_GT(r.seen[i], r.seen[i - 1]);
}

TEST(MockCamera, WithoutOverrunDropsASlowGeneratorFallsEverFurtherBehind) {
  // The behaviour the test above rules out: every frame delivered, each ~10 ms later than the one
  // before, so the 40th is ~400 ms old (more on a loaded machine, never less).
  const SlowRun r = run_slow_camera(false);
  ASSERT_EQ(r.seen.size(), 40u);
  EXPECT_EQ(r.overruns, 0u);
  EXPECT_EQ(r.dropped, 0u);
  EXPECT_GT(r.worst_age_ns, 300'000'000);
  // The measure the test above bounds at 100 ms: ~305 ms idle here, ~350 ms under stress-ng
  // --cpu 2 (and 4 ms / -7..6 ms for the test above).
  EXPECT_GT(r.growth_ms(), 200.0);
}

TEST(MockCamera, GeneratorCallbackFillsFrames) {
  MockCamera cam({.width = 4, .height = 4, .rate_hz = 500.0, .generator = [](Frame& f, uint64_t s) {
                    std::fill(f.data.begin(), f.data.end(), static_cast<uint8_t>(s & 0xFF));
                  }});
  cam.start();
  ASSERT_TRUE(
      eventually([&] { return cam.frames().fetch() && cam.frames().latest().sequence > 2; }));
  const Frame& f = cam.frames().latest();
  EXPECT_EQ(f.data[17], static_cast<uint8_t>(f.sequence & 0xFF));
  cam.stop();
}

TEST(MockCamera, BadSizeOrRateThrowsNamingTheCamera) {
  MockCamera bad({.id = "cam-left", .width = 0});
  try {
    bad.open();
    FAIL();
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("cam-left"), std::string::npos);
  }
  MockCamera slow({.rate_hz = 0});
  EXPECT_THROW(slow.open(), DeviceError);
}

}  // namespace
}  // namespace hd::drivers
