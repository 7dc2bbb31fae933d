#include "station/tracking/aligned_pose_source.h"

#include <chrono>
#include <stdexcept>
#include <utility>

namespace hd::station {

AlignedPoseSource::AlignedPoseSource(drivers::PoseSource& inner, AlignedPoseSourceConfig config)
    : inner_(inner), config_(std::move(config)), alignment_(config_.alignment) {
  if (!(config_.idle_sleep_ns > 0 && config_.idle_sleep_ns <= 100'000'000))
    throw std::invalid_argument("aligned pose source '" + inner_.id() +
                                "': idle_sleep_ns must be in (0, 100 ms]");
}

AlignedPoseSource::~AlignedPoseSource() {
  stop();
}

void AlignedPoseSource::start() {
  if (running_) return;
  inner_.start();
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void AlignedPoseSource::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
  inner_.stop();
}

uint64_t AlignedPoseSource::rejected_reports() const {
  return inner_.rejected_reports() + rejected_.load(std::memory_order_relaxed);
}

int AlignedPoseSource::pump() {
  int published = 0;
  drivers::PoseSample in;
  while (inner_.history().pop(in)) {
    if (recentre_requested_.exchange(false, std::memory_order_acq_rel)) {
      if (alignment_.recentre(in)) {
        recentres_.store(alignment_.recentres(), std::memory_order_relaxed);
      } else {
        // An invalid sample cannot anchor the re-centre: keep the request for the next one.
        recentre_requested_.store(true, std::memory_order_release);
      }
    }
    drivers::PoseSample& out = latest_.write_slot();
    if (!alignment_.align(in, out)) {
      rejected_.store(alignment_.rejected(), std::memory_order_relaxed);
      continue;
    }
    history_.push(out);
    latest_.publish();
    tracker_resets_.store(alignment_.tracker_resets(), std::memory_order_relaxed);
    samples_.fetch_add(1, std::memory_order_relaxed);
    ++published;
  }
  return published;
}

void AlignedPoseSource::run() {
  while (running_.load(std::memory_order_acquire)) {
    if (pump() == 0) std::this_thread::sleep_for(std::chrono::nanoseconds(config_.idle_sleep_ns));
  }
}

}  // namespace hd::station
