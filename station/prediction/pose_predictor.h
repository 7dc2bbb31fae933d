#pragma once
// What every head pose predictor offers the frame loop.

#include <cstdint>
#include <string_view>

#include "core/pose.h"
#include "station/prediction/head_sample.h"

namespace hd::station {

/// Fed every accepted sample in time order; asked for the pose at the expected display time.
/// Nothing here allocates: predictors are fixed-size state.
class PosePredictor {
 public:
  virtual ~PosePredictor() = default;
  virtual std::string_view name() const = 0;
  /// Forget everything (the tracker's reference frame jumped).
  virtual void reset() = 0;
  virtual void observe(const HeadSample& s) = 0;
  /// At least one sample observed.
  virtual bool ready() const = 0;
  /// The head pose at `t_ns` (CLOCK_MONOTONIC). Before any sample: identity.
  virtual core::Pose predict(int64_t t_ns) const = 0;
};

/// The "no prediction" baseline: the newest sample, whatever the requested time.
class HoldPredictor final : public PosePredictor {
 public:
  std::string_view name() const override { return "none"; }
  void reset() override { has_ = false; }
  void observe(const HeadSample& s) override {
    last_ = s;
    has_ = true;
  }
  bool ready() const override { return has_; }
  core::Pose predict(int64_t /*t_ns*/) const override {
    return has_ ? core::Pose::from(last_.q_world_head, last_.p_world_m) : core::Pose::identity();
  }

 private:
  HeadSample last_{};
  bool has_ = false;
};

}  // namespace hd::station
