#pragma once
// The CPU passes' second thread: a persistent worker that draws part of a picture's rows while the
// calling thread draws the rest, so a pass runs on two cores without a thread per frame.

#include <atomic>
#include <cstdint>
#include <thread>
#include <type_traits>

namespace hd::render {

/// Runs a row function over rows [0, rows) on the calling thread and, with two threads, on one
/// persistent worker thread too; run() returns once every row is done. Each row is given to
/// exactly one call, so a pass that computes each row the same way gives the same bytes whatever
/// the thread count.
///
/// How the rows are shared (Split):
///  - kHalves: the caller draws [0, rows / 2) and the worker [rows / 2, rows), one call each
///    (thread 0 and thread 1: per-thread scratch can be indexed by it).
///  - kClaimed: both threads claim `rows_per_take` rows at a time from a shared counter until none
///    are left, so the work splits evenly whatever the rows cost and however late the worker
///    wakes (or, on a busy machine, the caller does them all).
///
/// The worker sleeps on an atomic between frames (frames come a display period apart). The caller
/// waits for the worker's last rows on an atomic too; with `spin` it first spins for up to 200 µs
/// (a futex wake-up can cost tens of microseconds, more than the wait for a balanced split).
/// run() allocates nothing and takes the row function by reference (no std::function).
/// With one thread, or fewer than two rows, the caller draws all rows in one call (thread 0).
/// Not reentrant: one run() at a time.
class RowWorker {
 public:
  enum class Split { kHalves, kClaimed };

  /// `threads` is 1 or 2 (the owner's clamp decides which). A second thread starts here.
  explicit RowWorker(int threads, Split split = Split::kHalves, int rows_per_take = 4,
                     bool spin = false);
  /// Stops the worker (it finishes nothing: no run() is in progress) and joins it.
  ~RowWorker();
  RowWorker(const RowWorker&) = delete;
  RowWorker& operator=(const RowWorker&) = delete;

  int threads() const { return threads_; }

  /// Calls rows_fn(row_begin, row_end, thread) until every row of [0, rows) was given once;
  /// thread is 0 for the calling thread, 1 for the worker.
  template <typename F>
  void run(int rows, F& rows_fn) {
    static_assert(std::is_invocable_v<F&, int, int, int>);
    run_erased(rows, &rows_fn, [](void* f, int begin, int end, int thread) {
      (*static_cast<F*>(f))(begin, end, thread);
    });
  }

 private:
  using Call = void (*)(void*, int, int, int);
  void run_erased(int rows, void* context, Call call);
  void worker_loop();
  /// Draws this thread's share: its half, or claimed groups until none are left.
  void take_rows(int thread);

  int threads_ = 1;
  Split split_ = Split::kHalves;
  int rows_per_take_ = 4;
  bool spin_ = false;

  // The job, written by run() before it publishes the job (claim_ and job_, release) and read by
  // the worker after it saw that (kHalves: job_; kClaimed: a successful claim, acquire). The
  // caller waits for every row it hands out, so it never rewrites these while the worker may
  // still read them.
  int rows_ = 0;
  void* context_ = nullptr;
  Call call_ = nullptr;

  // Each on its own cache line: both threads claim rows and count them done at the same time.
  alignas(64) std::atomic<uint64_t> job_{0};  ///< incremented to start the worker on a job
  /// kClaimed: rows << 32 | next row to claim. The row count travels with the counter, so a worker
  /// that wakes late (after the caller did every row and started the next frame) reads a claim
  /// that is either of the current job or past its end, never a row count being rewritten.
  alignas(64) std::atomic<uint64_t> claim_{0};
  alignas(64) std::atomic<int> rows_done_{0};
  alignas(64) std::atomic<bool> quit_{false};
  std::thread worker_;  ///< last: started once everything above is initialised
};

}  // namespace hd::render
