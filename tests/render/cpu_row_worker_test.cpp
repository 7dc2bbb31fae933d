// The CPU passes' row worker: every row given exactly once at any thread count, the workers'
// shares done before run() returns, a thread count outside its range refused, a clean stop, and no
// allocation per run. The threads wait for each other through atomics, never for time.
#include "render/cpu/row_worker.h"

#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/allocation_counter.h"

namespace hd::render {
namespace {

// One row function's record: how often each row was given, and by which thread.
struct Record {
  explicit Record(int rows) : count(static_cast<std::size_t>(rows)), thread(count.size()) {}
  std::vector<std::atomic<int>> count;
  std::vector<std::atomic<int>> thread;
  void take(int begin, int end, int t) {
    for (int r = begin; r < end; ++r) {
      count[static_cast<std::size_t>(r)].fetch_add(1);
      thread[static_cast<std::size_t>(r)].store(t);
    }
  }
  bool each_once() const {
    for (const auto& c : count)
      if (c.load() != 1) return false;
    return true;
  }
};

TEST(RowWorker, EveryRowIsGivenExactlyOnceWhateverTheSplitAndCount) {
  for (const RowWorker::Split split : {RowWorker::Split::kBands, RowWorker::Split::kClaimed}) {
    for (const int threads : {1, 2, 3, 8}) {
      RowWorker w(threads, split, 3);
      EXPECT_EQ(w.threads(), threads);
      // Several runs on one worker, with row counts that change (a new viewport size).
      for (const int rows : {1, 2, 3, 7, 100, 5, 1000}) {
        Record rec(rows);
        auto fn = [&rec](int b, int e, int t) { rec.take(b, e, t); };
        w.run(rows, fn);
        EXPECT_TRUE(rec.each_once())
            << "split " << static_cast<int>(split) << " threads " << threads << " rows " << rows;
      }
      int calls = 0;
      auto none = [&calls](int, int, int) { ++calls; };
      w.run(0, none);
      EXPECT_EQ(calls, 0);
    }
  }
}

TEST(RowWorker, OneThreadDrawsEverythingInOneCallOnTheCaller) {
  RowWorker w(1);
  const std::thread::id caller = std::this_thread::get_id();
  int calls = 0;
  auto fn = [&](int b, int e, int t) {
    ++calls;
    EXPECT_EQ(b, 0);
    EXPECT_EQ(e, 10);
    EXPECT_EQ(t, 0);
    EXPECT_EQ(std::this_thread::get_id(), caller);
  };
  w.run(10, fn);
  EXPECT_EQ(calls, 1);
}

TEST(RowWorker, TwoBandsRunTogetherAndTheWorkersBandIsDoneBeforeRunReturns) {
  RowWorker w(2, RowWorker::Split::kBands);
  const std::thread::id caller = std::this_thread::get_id();
  for (const int rows : {2, 9, 480}) {
    std::atomic<bool> worker_started{false}, caller_finished{false};
    std::atomic<int> worker_rows_done{0};
    std::thread::id worker_id;
    int caller_begin = -1, caller_end = -1, worker_begin = -1, worker_end = -1;
    auto fn = [&](int b, int e, int t) {
      if (t == 0) {
        caller_begin = b;
        caller_end = e;
        // The caller's half waits for the worker to be drawing: both halves run at once.
        while (!worker_started.load()) std::this_thread::yield();
        caller_finished.store(true);
      } else {
        worker_id = std::this_thread::get_id();
        worker_begin = b;
        worker_end = e;
        worker_started.store(true);
        // The worker finishes only after the caller's half: run() must still wait for it.
        while (!caller_finished.load()) std::this_thread::yield();
        worker_rows_done.store(e - b);
      }
    };
    w.run(rows, fn);
    EXPECT_EQ(worker_rows_done.load(), rows - rows / 2) << rows;
    EXPECT_EQ(caller_begin, 0);
    EXPECT_EQ(caller_end, rows / 2);
    EXPECT_EQ(worker_begin, rows / 2);
    EXPECT_EQ(worker_end, rows);
    EXPECT_NE(worker_id, caller);
  }
}

TEST(RowWorker, NBandsAreEqualToARowAndEachThreadDrawsItsOwn) {
  for (const int threads : {3, 5, 8}) {
    RowWorker w(threads, RowWorker::Split::kBands);
    for (const int rows : {threads, 100, 481}) {
      std::vector<std::atomic<int>> begin(static_cast<std::size_t>(threads));
      std::vector<std::atomic<int>> end(static_cast<std::size_t>(threads));
      std::vector<std::thread::id> ids(static_cast<std::size_t>(threads));
      for (auto& b : begin) b.store(-1);
      auto fn = [&](int b, int e, int t) {
        begin[static_cast<std::size_t>(t)].store(b);
        end[static_cast<std::size_t>(t)].store(e);
        ids[static_cast<std::size_t>(t)] = std::this_thread::get_id();
      };
      w.run(rows, fn);
      int next = 0;
      for (int t = 0; t < threads; ++t) {
        const auto i = static_cast<std::size_t>(t);
        EXPECT_EQ(begin[i].load(), next) << threads << " threads, band " << t;
        const int size = end[i].load() - begin[i].load();
        EXPECT_GE(size, rows / threads) << threads << " threads, band " << t;
        EXPECT_LE(size, rows / threads + 1) << threads << " threads, band " << t;
        next = end[i].load();
        for (int u = 0; u < t; ++u) EXPECT_NE(ids[i], ids[static_cast<std::size_t>(u)]);
      }
      EXPECT_EQ(next, rows);
    }
  }
}

TEST(RowWorker, AThreadCountOutsideItsRangeIsRefusedNotChanged) {
  EXPECT_THROW(RowWorker(0), std::invalid_argument);
  EXPECT_THROW(RowWorker(RowWorker::kMaxThreads + 1), std::invalid_argument);
  try {
    RowWorker w(9);
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "CPU pass threads: 9 is outside 1..8");
  }
  EXPECT_EQ(RowWorker(RowWorker::kMaxThreads).threads(), RowWorker::kMaxThreads);
}

TEST(RowWorker, ClaimedRowsComeInGroupsAndTheWorkerTakesSome) {
  constexpr int kTake = 4;
  RowWorker w(2, RowWorker::Split::kClaimed, kTake);
  for (int run = 0; run < 3; ++run) {
    const int rows = 41;
    Record rec(rows);
    std::atomic<bool> worker_claimed{false};
    std::atomic<bool> groups_ok{true};
    std::atomic<int> caller_calls{0};
    auto fn = [&](int b, int e, int t) {
      if (b % kTake != 0 || e - b > kTake || (e - b < kTake && e != rows)) groups_ok.store(false);
      // Each thread's first group waits until the other has claimed one, so both take part
      // however the two are scheduled (the worker set its flag before it waits, the caller
      // counted its call before it waits: neither waits for the other forever).
      if (t == 1 && !worker_claimed.exchange(true))
        while (caller_calls.load() == 0) std::this_thread::yield();
      if (t == 0 && caller_calls.fetch_add(1) == 0)
        while (!worker_claimed.load()) std::this_thread::yield();
      rec.take(b, e, t);
    };
    w.run(rows, fn);
    EXPECT_TRUE(rec.each_once());
    EXPECT_TRUE(groups_ok.load());
    int by_worker = 0;
    for (const auto& t : rec.thread) by_worker += t.load() == 1;
    EXPECT_GT(by_worker, 0);
    EXPECT_LT(by_worker, rows);  // the caller's first group at least
  }
}

TEST(RowWorker, StopsCleanlyWithOrWithoutWork) {
  // Destroyed before any run, and after runs (a hang here fails the test by its time-out).
  { RowWorker idle(2, RowWorker::Split::kClaimed); }
  { RowWorker idle(2, RowWorker::Split::kBands); }
  auto w = std::make_unique<RowWorker>(2, RowWorker::Split::kBands);
  std::atomic<int> rows_seen{0};
  auto fn = [&](int b, int e, int) { rows_seen.fetch_add(e - b); };
  w->run(64, fn);
  w.reset();
  EXPECT_EQ(rows_seen.load(), 64);
}

TEST(RowWorker, RunAllocatesNothing) {
  for (const RowWorker::Split split : {RowWorker::Split::kBands, RowWorker::Split::kClaimed}) {
    RowWorker w(2, split);
    std::atomic<int> rows_seen{0};
    auto fn = [&](int b, int e, int) { rows_seen.fetch_add(e - b); };
    w.run(100, fn);  // the worker is running before counting starts
    core::reset_counted_allocations();
    core::count_allocations_on_all_threads(true);
    for (int i = 0; i < 50; ++i) w.run(100, fn);
    core::count_allocations_on_all_threads(false);
    EXPECT_EQ(core::counted_allocations(), 0u);
    EXPECT_EQ(rows_seen.load(), 51 * 100);
  }
}

}  // namespace
}  // namespace hd::render
