// The per-frame decision allocates nothing: the global operator new/delete are replaced in this
// binary and counted while measure_view + Transition::update + video_weight run.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "core/blend_weights.h"
#include "core/transition.h"
#include "core/view_measure.h"
#include "setups.h"

// GCC 12 with -fsanitize inlines gtest's delete into this replacement and then flags malloc/free
// as a new/delete mismatch; the pairing here is malloc/free on both sides, so silence it.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  return operator new(n);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

TEST(Allocation, CounterSeesAnAllocation) {
  const long before = g_allocations.load();
  void* p = ::operator new(sizeof(int));  // a direct call cannot be elided, unlike new-expressions
  ::operator delete(p);
  EXPECT_EQ(g_allocations.load() - before, 1);
}

TEST(Allocation, PerFrameDecisionAllocatesNothing) {
  using namespace hd::core;
  ViewSetup s = test::example_setup();
  Transition t({});
  t.update(10, 0.01);  // warm-up
  double sink = 0;
  const long before = g_allocations.load();
  for (int i = 0; i < 200; ++i) {
    s.T_world_virt.t.x() = 0.001 * i;
    s.T_world_virt.R = test::rot(0.002 * i, 0.001 * i, 0);
    const ViewMeasure vm = measure_view(s);
    const TransitionState st = t.update(vm.m, 0.011);
    sink += st.w_video + video_weight(vm.m, 40, 10) + vm.region.u_min;
  }
  const long after = g_allocations.load();
  EXPECT_EQ(after - before, 0);
  EXPECT_TRUE(std::isfinite(sink));
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
