#pragma once
// The CPU passes' extra threads: persistent workers that draw parts of a picture's rows while the
// calling thread draws the rest, so a pass runs on several cores without a thread per frame.

#include <atomic>
#include <cstdint>
#include <thread>
#include <type_traits>
#include <vector>

namespace hd::render {

/// Runs a row function over rows [0, rows) on the calling thread and on threads - 1 persistent
/// worker threads; run() returns once every row is done. Each row is given to exactly one call,
/// so a pass that computes each row the same way gives the same bytes whatever the thread count.
///
/// How the rows are shared (Split), with N threads numbered 0 (the caller) to N - 1:
///  - kBands: thread t draws [t rows / N, (t + 1) rows / N), one call each (per-thread scratch
///    can be indexed by t).
///  - kClaimed: every thread claims `rows_per_take` rows at a time from a shared counter until
///    none are left, so the work splits evenly whatever the rows cost and however late a worker
///    wakes (or, on a busy machine, the caller does them all).
///
/// Workers sleep on an atomic between frames (frames come a display period apart). The caller
/// waits for the workers' last rows on an atomic too; with `spin` it first spins for up to 200 µs
/// (a futex wake-up can cost tens of microseconds, more than the wait for a balanced split).
/// run() allocates nothing and takes the row function by reference (no std::function).
/// With one thread, or fewer rows than threads, the caller draws all rows in one call (thread 0).
/// Not reentrant: one run() at a time.
class RowWorker {
 public:
  enum class Split { kBands, kClaimed };
  /// More threads than this is refused: no CPU pass here gains beyond it (rows of a few hundred
  /// pixels; the wake-ups and the memory bus cost more).
  static constexpr int kMaxThreads = 8;

  /// `threads` in 1..kMaxThreads (std::invalid_argument otherwise, naming the range: a thread
  /// count is never silently changed). The workers start here.
  explicit RowWorker(int threads, Split split = Split::kBands, int rows_per_take = 4,
                     bool spin = false);
  /// Stops the workers (they finish nothing: no run() is in progress) and joins them.
  ~RowWorker();
  RowWorker(const RowWorker&) = delete;
  RowWorker& operator=(const RowWorker&) = delete;

  int threads() const { return threads_; }

  /// Calls rows_fn(row_begin, row_end, thread) until every row of [0, rows) was given once;
  /// thread is 0 for the calling thread, 1..threads - 1 for the workers.
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
  void worker_loop(int thread);
  /// Draws this thread's share: its band, or claimed groups until none are left.
  void take_rows(int thread);

  int threads_ = 1;
  Split split_ = Split::kBands;
  int rows_per_take_ = 4;
  bool spin_ = false;

  // The job, written by run() before it publishes the job (claim_ and job_, release) and read by
  // the workers after they saw that (kBands: job_; kClaimed: a successful claim, acquire). The
  // caller waits for every row it hands out, so it never rewrites these while a worker may
  // still read them.
  int rows_ = 0;
  void* context_ = nullptr;
  Call call_ = nullptr;

  // Each on its own cache line: both threads claim rows and count them done at the same time.
  alignas(64) std::atomic<uint64_t> job_{0};  ///< incremented to start the workers on a job
  /// kClaimed: rows << 32 | next row to claim. The row count travels with the counter, so a worker
  /// that wakes late (after the caller did every row and started the next frame) reads a claim
  /// that is either of the current job or past its end, never a row count being rewritten.
  alignas(64) std::atomic<uint64_t> claim_{0};
  alignas(64) std::atomic<int> rows_done_{0};
  alignas(64) std::atomic<bool> quit_{false};
  std::vector<std::thread> workers_;  ///< last: started once everything above is initialised
};

}  // namespace hd::render
