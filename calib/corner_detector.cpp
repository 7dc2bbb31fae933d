#include "calib/corner_detector.h"

#include "calib/larger_board_probe.h"

#include <time.h>

#include <algorithm>
#include <condition_variable>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

namespace hd::calib {

namespace {

// CPU time of the calling thread (the detection runs on its own worker thread).
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

Detection run_detection(const cv::Mat& gray, const Board& board, const DetectorOptions& opt) {
  Detection d;
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_s();
  bool found = false;
  if (opt.use_classic) {
    found = cv::findChessboardCorners(
        gray, board.pattern(), d.corners,
        cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
    if (found && opt.refinement != Refinement::kNone) {
      // "11x11" is cornerSubPix's winSize as OpenCV's calibration samples pass it: the HALF
      // size, i.e. a 23x23 search window (the published reference figures used it).
      // A window reaching past the neighbouring corners pulls the estimate towards them (small
      // or distant boards), so it is capped at 0.6x the closest corner spacing.
      // Both directions count: a board tilted about its rows is foreshortened along its columns.
      double spacing = 1e9;
      const auto cols = static_cast<std::size_t>(board.cols);
      for (int r = 0; r < board.rows; ++r)
        for (int c = 0; c < board.cols; ++c) {
          const auto i = static_cast<std::size_t>(r * board.cols + c);
          if (c + 1 < board.cols)
            spacing =
                std::min(spacing, static_cast<double>(cv::norm(d.corners[i + 1] - d.corners[i])));
          if (r + 1 < board.rows)
            spacing = std::min(spacing,
                               static_cast<double>(cv::norm(d.corners[i + cols] - d.corners[i])));
        }
      const int win = std::max(2, std::min(opt.refinement == Refinement::kSubPix11 ? 11 : 5,
                                           static_cast<int>(0.6 * spacing)));
      cv::cornerSubPix(gray, d.corners, cv::Size(win, win), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 1e-4));
    }
  }
  if (!found && opt.use_sb_fallback) {
    // SB localises corners itself (sub-pixel by design); refining again with cornerSubPix would
    // only mix two estimators, so its corners are kept as they are.
    d.corners.clear();
    found = cv::findChessboardCornersSB(
        gray, board.pattern(), d.corners,
        cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY);
    d.by_sb = found;
  }
  if (found && static_cast<int>(d.corners.size()) != board.corner_count()) found = false;
  const double cpu_found = thread_cpu_s();
  // SB's larger-board search costs as much as a detection: only where the checker visibly goes
  // on past an edge of the found pattern.
  if (found && opt.check_larger && probe_beyond_edges(gray, board, d.corners).continues) {
    d.larger_corner_count = larger_board_corners(gray, board);
    d.larger_check_cpu_s = thread_cpu_s() - cpu_found;
    if (d.larger_corner_count > 0) {
      d.status = DetectionStatus::kLargerBoard;
      d.corners.clear();
      d.cpu_s = thread_cpu_s() - cpu0;
      d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return d;
    }
  }
  d.status = found ? DetectionStatus::kFound : DetectionStatus::kNotFound;
  if (!found) d.corners.clear();
  d.cpu_s = thread_cpu_s() - cpu0;
  d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return d;
}

// Shared between the caller and a worker that may outlive the call.
struct Job {
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  bool abandoned = false;  ///< past its deadline: counted in Abandoned until it ends
  Detection result;
};

// The workers abandoned at their deadline that are still running. The process waits for them
// at exit: one still inside OpenCV when OpenCV's statics were destroyed aborted the program
// ("Can't fetch data from terminated TLS container", exit 134 instead of 1, seen with the CPUs
// saturated). The wait is registered with atexit when the first worker is abandoned, after
// OpenCV's statics exist, so it runs before they are destroyed. OpenCV's detection always ends;
// it is only slow. Never destroyed (a worker may still use it during exit).
struct Abandoned {
  std::mutex m;
  std::condition_variable cv;
  int running = 0;
};

Abandoned& abandoned() {
  static Abandoned* a = new Abandoned;
  return *a;
}

void wait_for_abandoned_workers() {
  Abandoned& a = abandoned();
  std::unique_lock lock(a.m);
  a.cv.wait(lock, [&] { return a.running == 0; });
}

}  // namespace

int larger_board_corners(const cv::Mat& gray, const Board& board) {
  std::vector<cv::Point2f> larger;
  if (cv::findChessboardCornersSB(gray, board.pattern(), larger,
                                  cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_LARGER) &&
      static_cast<int>(larger.size()) > board.corner_count())
    return static_cast<int>(larger.size());
  return 0;
}

std::string Detection::describe() const {
  switch (status) {
    case DetectionStatus::kFound:
      return by_sb ? "board found (SB fallback)" : "board found";
    case DetectionStatus::kNotFound:
      return "no board";
    case DetectionStatus::kTimedOut:
      return "detection timed out, skipped";
    case DetectionStatus::kLargerBoard:
      return "pattern is part of a larger board (" + std::to_string(larger_corner_count) +
             " inner corners): wrong --board?";
  }
  return "?";
}

Detection detect_corners(const cv::Mat& gray, const Board& board, const DetectorOptions& opt) {
  CV_Assert(gray.type() == CV_8UC1);
  auto job = std::make_shared<Job>();
  cv::Mat image = gray.clone();  // the worker may outlive the caller's buffer
  std::thread worker([job, image, board, opt] {
    Detection d = run_detection(image, board, opt);
    std::lock_guard lock(job->m);
    job->result = std::move(d);
    job->done = true;
    job->cv.notify_all();
    if (job->abandoned) {
      Abandoned& a = abandoned();
      std::lock_guard count(a.m);
      --a.running;
      a.cv.notify_all();
    }
  });
  std::unique_lock lock(job->m);
  if (job->cv.wait_for(lock, opt.timeout, [&] { return job->done; })) {
    lock.unlock();
    worker.join();
    return std::move(job->result);
  }
  // Still running, under job->m: it counts itself out when it ends.
  job->abandoned = true;
  {
    Abandoned& a = abandoned();
    std::lock_guard count(a.m);
    ++a.running;
  }
  static std::once_flag registered;
  std::call_once(registered, [] { std::atexit(wait_for_abandoned_workers); });
  lock.unlock();
  worker.detach();  // OpenCV offers no cancellation; the worker ends on its own.
  Detection d;
  d.status = DetectionStatus::kTimedOut;
  d.seconds = std::chrono::duration<double>(opt.timeout).count();
  return d;
}

}  // namespace hd::calib
