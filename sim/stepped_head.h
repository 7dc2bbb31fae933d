#pragma once
// A scene's head tracker driven by the scene's clock instead of a thread: advance_to(t)
// publishes every sample the running tracker (the Simulation's MockPoseSource) would have
// published by host time t, on its rate's grid from scene t = 0, with the scene's tracker effects
// (Simulation::head_sample), into the same history ring and mailbox the station reads.

#include <cstdint>
#include <string>

#include "drivers/pose_source.h"
#include "sim/simulation.h"

namespace hd::sim {

class SteppedHead final : public drivers::PoseSource {
 public:
  /// `sim` must outlive it; scene t = 0 at host time epoch_ns.
  SteppedHead(const Simulation& sim, int64_t epoch_ns);

  std::string id() const override { return "sim:head"; }
  void open() override {}
  void start() override { running_ = true; }
  void stop() override { running_ = false; }
  drivers::SourceState state() const override;
  uint64_t rejected_reports() const override { return 0; }
  drivers::Mailbox<drivers::PoseSample>& latest() override { return latest_; }
  drivers::SpscRing<drivers::PoseSample, 1024>& history() override { return history_; }

  /// Publishes every sample due by host time now_ns; returns how many.
  uint64_t advance_to(int64_t now_ns);

 private:
  const Simulation& sim_;
  int64_t epoch_ns_;
  int64_t period_ns_;
  bool running_ = false;
  uint64_t next_sequence_ = 0;
  drivers::Mailbox<drivers::PoseSample> latest_;
  drivers::SpscRing<drivers::PoseSample, 1024> history_;
};

}  // namespace hd::sim
