// FrameLoop on a fake clock: slot times, display time, missed deadlines and skipped slots.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "render/loop/frame_loop.h"

namespace hd::render {
namespace {

class FakeClock final : public LoopClock {
 public:
  int64_t now_ns() override { return now; }
  void sleep_until_ns(int64_t t) override {
    sleeps.push_back(t);
    if (t > now) now = t;
  }
  int64_t now = 5'000'000'000;
  std::vector<int64_t> sleeps;
};

// Work that takes a scripted time per frame on the fake clock.
class ScriptedWork final : public FrameWork {
 public:
  ScriptedWork(FakeClock& c, std::vector<int64_t> cost) : clock(c), cost_ns(std::move(cost)) {}
  void tick(const FrameTiming& t) override {
    seen.push_back(t);
    clock.now += cost_ns[seen.size() - 1];
  }
  FakeClock& clock;
  std::vector<int64_t> cost_ns;
  std::vector<FrameTiming> seen;
};

TEST(LoopFrameLoop, SlotsDeadlinesAndDisplayTime) {
  FakeClock clock;
  FrameLoopConfig cfg;
  cfg.rate_hz = 90.0;
  cfg.scanout_latency_ns = 4'000'000;
  FrameLoop loop(cfg, clock);
  const int64_t period = 11'111'111;  // round(1e9 / 90)
  ASSERT_EQ(loop.period_ns(), period);
  ScriptedWork work(clock, std::vector<int64_t>(5, 2'000'000));
  loop.run(5, work);
  for (int k = 0; k < 5; ++k) {
    const FrameTiming& t = work.seen[static_cast<std::size_t>(k)];
    EXPECT_EQ(t.frame, static_cast<uint64_t>(k));
    EXPECT_EQ(t.start_ns, 5'000'000'000 + k * period);
    EXPECT_EQ(t.deadline_ns, t.start_ns + period);
    EXPECT_EQ(t.display_ns, t.start_ns + period + 4'000'000);
    EXPECT_EQ(clock.sleeps[static_cast<std::size_t>(k)], t.start_ns);  // absolute sleeps
    EXPECT_NEAR(t.dt_s, k == 0 ? 0.0 : period * 1e-9, 1e-15);
  }
  EXPECT_EQ(loop.missed_deadlines(), 0u);
  EXPECT_EQ(loop.skipped_slots(), 0u);
}

TEST(LoopFrameLoop, LateFramesAreCountedAndTheLoopStaysPhaseLocked) {
  FakeClock clock;
  FrameLoopConfig cfg;
  cfg.rate_hz = 60.0;
  FrameLoop loop(cfg, clock);
  const int64_t p = loop.period_ns();
  // Frame 1 takes 2.5 periods: it misses its deadline and the next two slots have started
  // before it ends; frame 2 starts on the slot after that (slot 4).
  ScriptedWork work(clock, {p / 2, 5 * p / 2, p / 2, p / 2});
  loop.run(4, work);
  EXPECT_EQ(loop.missed_deadlines(), 1u);
  EXPECT_EQ(loop.skipped_slots(), 2u);
  const int64_t t0 = work.seen[0].start_ns;
  EXPECT_EQ(work.seen[1].start_ns, t0 + p);
  EXPECT_EQ(work.seen[2].start_ns, t0 + 4 * p);
  EXPECT_EQ(work.seen[3].start_ns, t0 + 5 * p);
  EXPECT_NEAR(work.seen[2].dt_s, 3 * p * 1e-9, 1e-12);
}

TEST(LoopFrameLoop, ADivisorLengthensThePeriodOnTheDisplaysVsyncGrid) {
  FakeClock clock;
  FrameLoop loop(FrameLoopConfig{90.0, 0, true}, clock);
  const int64_t p = loop.period_ns();
  // Two frames at 90 Hz, then a third of it: slots 3 display periods apart; frame 4 overruns its
  // 3-period slot by half a display period and joins the display's next vsync (no slot of 3).
  ScriptedWork work(clock, {p / 2, p / 2, 2 * p, 7 * p / 2, p});
  loop.tick(work);
  loop.tick(work);
  loop.set_divisor(3);
  EXPECT_EQ(loop.period_ns(), 3 * p);
  EXPECT_EQ(loop.divisor(), 3);
  loop.tick(work);
  loop.tick(work);
  loop.tick(work);
  const int64_t t0 = work.seen[0].start_ns;
  EXPECT_EQ(work.seen[1].start_ns, t0 + p);
  EXPECT_EQ(work.seen[2].start_ns, t0 + 2 * p);
  EXPECT_EQ(work.seen[2].deadline_ns, t0 + 5 * p);
  EXPECT_EQ(work.seen[3].start_ns, t0 + 5 * p);  // 2 periods of work fit the 3 of its slot
  EXPECT_EQ(work.seen[4].start_ns, t0 + 9 * p);  // 3.5 periods: ended at 8.5, next vsync 9
  EXPECT_EQ(loop.missed_deadlines(), 1u);
  EXPECT_EQ(loop.skipped_slots(), 1u);  // display periods passed with no frame starting
  EXPECT_EQ(loop.last_work_ns(), p);
  EXPECT_THROW(loop.set_divisor(0), std::invalid_argument);
}

TEST(LoopFrameLoop, RejectsBadRates) {
  FakeClock clock;
  EXPECT_THROW(FrameLoop(FrameLoopConfig{0.0, 0, true}, clock), std::invalid_argument);
  EXPECT_THROW(FrameLoop(FrameLoopConfig{NAN, 0, true}, clock), std::invalid_argument);
  EXPECT_THROW(FrameLoop(FrameLoopConfig{90.0, -1, true}, clock), std::invalid_argument);
  EXPECT_NO_THROW(FrameLoop(FrameLoopConfig{72.0, 0, true}, clock));
}

TEST(LoopFrameLoop, RealClockSleepsToAbsoluteSlots) {
  // Not a timing assertion: only that the loop did sleep until each slot start it reported.
  MonotonicLoopClock clock;
  FrameLoop loop(FrameLoopConfig{200.0, 0, true}, clock);
  struct Check final : FrameWork {
    MonotonicLoopClock* c;
    int early = 0;
    void tick(const FrameTiming& t) override { early += c->now_ns() < t.start_ns; }
  } w;
  w.c = &clock;
  loop.run(20, w);
  EXPECT_EQ(w.early, 0);
}

}  // namespace
}  // namespace hd::render
