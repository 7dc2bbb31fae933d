#pragma once
// Shows that a per-frame path allocates nothing: a program that links `hd_allocation_counter`
// gets a replacement global operator new that counts while counting is switched on.

#include <cstdint>

namespace hd::core {

/// Counts every operator new on every thread while on (tests of whole pipelines).
void count_allocations_on_all_threads(bool on);

/// Counts operator new on the calling thread while on (the render thread inside a tick, while
/// device threads allocate as they like).
void count_allocations_on_this_thread(bool on);

/// operator new calls counted so far, and a reset to zero.
uint64_t counted_allocations();
/// Of those, the ones the calling thread made (never reset: take differences). Lets one run count
/// a consumer thread and the whole process at once.
uint64_t counted_allocations_on_this_thread();
void reset_counted_allocations();

}  // namespace hd::core
