#pragma once
// The render side of a pose device: every sample from the device thread's ring, validated, kept
// in a fixed window and handed to a predictor.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "drivers/pose_source.h"
#include "station/prediction/head_sample.h"
#include "station/prediction/pose_predictor.h"

namespace hd::station {

/// Fixed-capacity history of accepted head samples (oldest overwritten). pull() drains a
/// PoseSource's SpscRing; bad samples (non-finite, not a rotation, time going backwards) are
/// rejected and counted, a bumped reset_counter clears the history and the predictor.
/// No allocation anywhere: the storage is an array member.
class PoseHistory {
 public:
  static constexpr std::size_t kCapacity = 256;
  using Ring = drivers::SpscRing<drivers::PoseSample, 1024>;

  /// Drains `ring`; returns how many samples were accepted. `predictor` may be null.
  int pull(Ring& ring, PosePredictor* predictor);

  /// Validates and stores one sample; false when rejected (see last_rejection()).
  bool add(const drivers::PoseSample& s, PosePredictor* predictor);

  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  /// i = 0 is the oldest kept sample, size()-1 the newest.
  const HeadSample& at(std::size_t i) const {
    return items_[(head_ + kCapacity - count_ + i) % kCapacity];
  }
  const HeadSample& newest() const { return at(count_ - 1); }

  uint64_t accepted() const { return accepted_; }
  uint64_t rejected() const { return rejected_; }
  uint64_t resets() const { return resets_; }
  /// Why the last sample was rejected (a string literal; empty if none was).
  std::string_view last_rejection() const { return last_rejection_; }

 private:
  std::array<HeadSample, kCapacity> items_{};
  std::size_t head_ = 0;  // next write index
  std::size_t count_ = 0;
  uint32_t reset_counter_ = 0;
  bool seen_any_ = false;
  uint64_t accepted_ = 0;
  uint64_t rejected_ = 0;
  uint64_t resets_ = 0;
  std::string_view last_rejection_{};
};

}  // namespace hd::station
