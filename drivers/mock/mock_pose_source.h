#pragma once
// A PoseSource replaying a trajectory file or a scripted motion at a set rate, for the simulated
// scene and for tests of everything downstream of the tracker.

#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "drivers/mock/trajectory.h"
#include "drivers/pose_source.h"

namespace hd::drivers {

/// Head pose (station axes) at time t seconds since start().
using ScriptedMotion = std::function<TrajectorySample(double t_s)>;

struct MockPoseSourceConfig {
  std::string id = "mock-pose";
  ScriptedMotion motion{};  ///< e.g. from_trajectory(Trajectory::load_csv(...))
  double rate_hz = 500.0;
  bool has_position = true;
  int64_t stall_timeout_ns = 100'000'000;
  /// Host time of the shared t = 0 (render/sim): samples on the grid epoch + k / rate_hz, the
  /// first at or after start(), with t_s measured from the epoch. Empty: from start().
  std::function<int64_t()> epoch_ns{};
  /// Applied to each sample before it is published (simulated tracker noise and drift).
  std::function<void(PoseSample& sample, double t_s)> sample_filter{};
};

ScriptedMotion from_trajectory(Trajectory trajectory);

class MockPoseSource : public PoseSource {
 public:
  explicit MockPoseSource(MockPoseSourceConfig config);
  ~MockPoseSource() override;
  MockPoseSource(const MockPoseSource&) = delete;
  MockPoseSource& operator=(const MockPoseSource&) = delete;

  std::string id() const override { return config_.id; }
  void open() override;  ///< throws DeviceError without a motion or with a bad rate
  void start() override;
  void stop() override;
  SourceState state() const override;
  uint64_t rejected_reports() const override { return 0; }
  Mailbox<PoseSample>& latest() override { return latest_; }
  SpscRing<PoseSample, 1024>& history() override { return history_; }

  /// The sample the source publishes for time t (pose + angular velocity by central difference).
  PoseSample sample_at(double t_s) const;

 private:
  void run();
  MockPoseSourceConfig config_;
  bool opened_ = false;
  std::atomic<bool> running_{false};
  std::atomic<int64_t> last_publish_ns_{0};
  std::thread thread_;
  Mailbox<PoseSample> latest_;
  SpscRing<PoseSample, 1024> history_;
};

}  // namespace hd::drivers
