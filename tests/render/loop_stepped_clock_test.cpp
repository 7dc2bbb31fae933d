// SteppedLoopClock: time moves only when a sleeper or the driver moves it, and never back on a
// sleep, whatever threads share it.
#include "render/loop/stepped_clock.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace hd::render {
namespace {

TEST(SteppedLoopClock, StandsStillUntilMoved) {
  SteppedLoopClock c(1'000);
  EXPECT_EQ(c.now_ns(), 1'000);
  EXPECT_EQ(c.now_ns(), 1'000);
  c.sleep_until_ns(5'000);  // a stage waiting: the wait is a jump
  EXPECT_EQ(c.now_ns(), 5'000);
  c.sleep_until_ns(2'000);  // already past: returns at once, time does not go back
  EXPECT_EQ(c.now_ns(), 5'000);
  c.set_ns(3'000);  // the driver may set any time
  EXPECT_EQ(c.now_ns(), 3'000);
}

TEST(SteppedLoopClock, ConcurrentSleepersLeaveTheLatestDeadline) {
  SteppedLoopClock c(0);
  std::vector<std::thread> threads;
  for (int i = 1; i <= 8; ++i)
    threads.emplace_back([&c, i] {
      for (int k = 0; k < 1000; ++k) c.sleep_until_ns(int64_t(i) * 1'000'000 + k);
    });
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(c.now_ns(), 8'000'999);
}

}  // namespace
}  // namespace hd::render
