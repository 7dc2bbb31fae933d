#pragma once
// A PoseSource that republishes another source's samples in the workspace frame, with a
// re-centre request any thread may make (the station's window key).

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "drivers/pose_source.h"
#include "station/tracking/tracker_alignment.h"

namespace hd::station {

struct AlignedPoseSourceConfig {
  TrackerAlignmentConfig alignment;
  /// How long the thread sleeps when the wrapped ring is empty (bounds the added latency).
  int64_t idle_sleep_ns = 200'000;
};

/// Decorator: its own thread drains the wrapped source's history() ring (it must be that ring's
/// only consumer), maps every sample through a TrackerAlignment and publishes it on this source's
/// latest() and history(). Samples come out with T_tracker_head = T_world_head, so the station
/// reading this source uses an identity T_world_tracker. reset_counter on the output counts
/// re-centres (world jumps), not tracker resets (made seamless here).
///
/// id(), state() and open() forward to the wrapped source; rejected_reports() is the wrapped
/// count plus samples this stage rejected (non-finite pose). start()/stop() start and stop both.
/// Per sample: no allocation, no lock. The wrapped source must outlive this one (the destructor
/// stops it).
class AlignedPoseSource final : public drivers::PoseSource {
 public:
  /// Throws std::invalid_argument for a bad alignment configuration.
  AlignedPoseSource(drivers::PoseSource& inner, AlignedPoseSourceConfig config);
  ~AlignedPoseSource() override;
  AlignedPoseSource(const AlignedPoseSource&) = delete;
  AlignedPoseSource& operator=(const AlignedPoseSource&) = delete;

  std::string id() const override { return inner_.id(); }
  void open() override { inner_.open(); }
  void start() override;
  void stop() override;
  drivers::SourceState state() const override { return inner_.state(); }
  uint64_t rejected_reports() const override;
  drivers::Mailbox<drivers::PoseSample>& latest() override { return latest_; }
  drivers::SpscRing<drivers::PoseSample, 1024>& history() override { return history_; }

  /// Any thread, never blocks: the next sample the source thread maps re-centres the tracker
  /// frame on the configured home pose. Several requests before that sample count once.
  void request_recentre() { recentre_requested_.store(true, std::memory_order_release); }

  uint64_t recentres() const { return recentres_.load(std::memory_order_relaxed); }
  uint64_t tracker_resets() const { return tracker_resets_.load(std::memory_order_relaxed); }
  uint64_t samples() const { return samples_.load(std::memory_order_relaxed); }

  /// Maps everything waiting in the wrapped ring on the calling thread (the thread's body; tests
  /// call it directly instead of start()). Not while the thread runs. Returns samples published.
  int pump();

 private:
  void run();

  drivers::PoseSource& inner_;
  AlignedPoseSourceConfig config_;
  TrackerAlignment alignment_;  ///< owned by whichever thread pumps
  std::atomic<bool> running_{false};
  std::atomic<bool> recentre_requested_{false};
  std::atomic<uint64_t> recentres_{0};
  std::atomic<uint64_t> tracker_resets_{0};
  std::atomic<uint64_t> samples_{0};
  std::atomic<uint64_t> rejected_{0};
  std::thread thread_;
  drivers::Mailbox<drivers::PoseSample> latest_;
  drivers::SpscRing<drivers::PoseSample, 1024> history_;
};

}  // namespace hd::station
