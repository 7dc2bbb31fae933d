#include "render/cpu/row_worker.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace hd::render {
namespace {

// Spin this long for the worker's rows before sleeping on the atomic: the two shares take about
// the same time, so the wait is short, and a futex wake-up can cost tens of microseconds.
constexpr auto kSpin = std::chrono::microseconds(200);

// Waits until `a` != `old` (spinning for at most kSpin first when `spin`); returns the new value.
template <typename T>
T wait_change(const std::atomic<T>& a, T old, bool spin) {
  T v = a.load(std::memory_order_acquire);
  if (spin && v == old) {
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int i = 0; v == old; ++i) {
#if defined(__x86_64__)
      _mm_pause();
#endif
      v = a.load(std::memory_order_acquire);
      if ((i & 63) == 63 && std::chrono::steady_clock::now() > until) break;
    }
  }
  while (v == old) {
    a.wait(old, std::memory_order_acquire);
    v = a.load(std::memory_order_acquire);
  }
  return v;
}

}  // namespace

RowWorker::RowWorker(int threads, Split split, int rows_per_take, bool spin)
    : threads_(threads), split_(split), rows_per_take_(std::max(1, rows_per_take)), spin_(spin) {
  if (threads < 1 || threads > kMaxThreads)
    throw std::invalid_argument("CPU pass threads: " + std::to_string(threads) + " is outside 1.." +
                                std::to_string(kMaxThreads));
  workers_.reserve(static_cast<std::size_t>(threads_ - 1));
  for (int t = 1; t < threads_; ++t) workers_.emplace_back([this, t] { worker_loop(t); });
}

RowWorker::~RowWorker() {
  if (workers_.empty()) return;
  quit_.store(true);
  job_.fetch_add(1, std::memory_order_release);
  job_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void RowWorker::worker_loop(int thread) {
  uint64_t seen = 0;
  for (;;) {
    // Frames come a display period apart: sleep on the atomic rather than spin between them.
    seen = wait_change(job_, seen, false);
    if (quit_.load()) return;
    take_rows(thread);
  }
}

void RowWorker::take_rows(int thread) {
  if (split_ == Split::kBands) {
    // 64-bit products: rows times threads stays far from overflow either way, but cheaply so.
    const int h = rows_;
    const auto begin = static_cast<int>(int64_t(h) * thread / threads_);
    const auto end = static_cast<int>(int64_t(h) * (thread + 1) / threads_);
    call_(context_, begin, end, thread);
    if (rows_done_.fetch_add(end - begin, std::memory_order_acq_rel) + (end - begin) == h)
      rows_done_.notify_one();
    return;
  }
  for (;;) {
    // acq_rel: a successful claim sees the job run() published before resetting claim_.
    const uint64_t c =
        claim_.fetch_add(static_cast<uint64_t>(rows_per_take_), std::memory_order_acq_rel);
    const int rows = static_cast<int>(c >> 32), r = static_cast<int>(c & 0xFFFFFFFFu);
    if (r >= rows) return;
    const int end = std::min(rows, r + rows_per_take_);
    call_(context_, r, end, thread);
    if (rows_done_.fetch_add(end - r, std::memory_order_acq_rel) + (end - r) == rows)
      rows_done_.notify_one();
  }
}

void RowWorker::run_erased(int rows, void* context, Call call) {
  if (rows <= 0) return;
  if (threads_ == 1 || rows < threads_) {
    call(context, 0, rows, 0);
    return;
  }
  rows_ = rows;
  context_ = context;
  call_ = call;
  rows_done_.store(0, std::memory_order_relaxed);
  claim_.store(static_cast<uint64_t>(rows) << 32, std::memory_order_release);
  job_.fetch_add(1, std::memory_order_release);
  job_.notify_all();
  take_rows(0);
  for (int d = rows_done_.load(std::memory_order_acquire); d != rows;)
    d = wait_change(rows_done_, d, spin_);
}

}  // namespace hd::render
