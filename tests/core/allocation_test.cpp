// The per-frame decision allocates nothing: this program links hd_allocation_counter, which
// replaces the global operator new and counts every call while measure_view + Transition::update +
// video_weight run.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <thread>

#include "core/allocation_counter.h"
#include "core/blend_weights.h"
#include "core/transition.h"
#include "core/view_measure.h"
#include "setups.h"

TEST(Allocation, CounterSeesAnAllocation) {
  const long before = static_cast<long>(hd::core::counted_allocations());
  void* p = ::operator new(sizeof(int));  // a direct call cannot be elided, unlike new-expressions
  ::operator delete(p);
  EXPECT_EQ(static_cast<long>(hd::core::counted_allocations()) - before, 1);
}

TEST(Allocation, ThisThreadsShareIsCountedApart) {
  // All threads are counted in this program (main): the total sees both threads, the calling
  // thread's count only its own two.
  const uint64_t all_before = hd::core::counted_allocations();
  const uint64_t mine_before = hd::core::counted_allocations_on_this_thread();
  uint64_t theirs = 0;
  std::thread other([&] {
    const uint64_t b = hd::core::counted_allocations_on_this_thread();
    for (int i = 0; i < 3; ++i) ::operator delete(::operator new(8));
    theirs = hd::core::counted_allocations_on_this_thread() - b;
  });
  other.join();
  for (int i = 0; i < 2; ++i) ::operator delete(::operator new(8));
  const uint64_t mine = hd::core::counted_allocations_on_this_thread() - mine_before;
  EXPECT_EQ(theirs, 3u);
  // std::thread's own start-up state is allocated by this thread, once.
  EXPECT_GE(mine, 2u);
  EXPECT_LE(mine, 3u);
  EXPECT_EQ(hd::core::counted_allocations() - all_before, mine + theirs);
}

TEST(Allocation, PerFrameDecisionAllocatesNothing) {
  using namespace hd::core;
  ViewSetup s = test::example_setup();
  Transition t({});
  t.update(10, 0.01);  // warm-up
  double sink = 0;
  const long before = static_cast<long>(hd::core::counted_allocations());
  for (int i = 0; i < 200; ++i) {
    s.T_world_virt.t.x() = 0.001 * i;
    s.T_world_virt.R = test::rot(0.002 * i, 0.001 * i, 0);
    const ViewMeasure vm = measure_view(s);
    const TransitionState st = t.update(vm.m, 0.011);
    sink += st.w_video + video_weight(vm.m, 40, 10) + vm.region.u_min;
  }
  const long after = static_cast<long>(hd::core::counted_allocations());
  EXPECT_EQ(after - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

int main(int argc, char** argv) {
  hd::core::count_allocations_on_all_threads(true);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
