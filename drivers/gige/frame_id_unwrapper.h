#pragma once
// GigE Vision block ids to a 64-bit frame sequence, with the drops the gaps imply.

#include <cstdint>

namespace hd::drivers {

/// GVSP 1.x block ids are 16 bits and skip 0 on wrap-around (65535 -> 1, 0 is reserved), so the
/// id space is a cycle of 65535 values, not 65536. GigE Vision 2 "extended ids" are 64 bits and
/// never wrap; an id above 65535 switches the unwrapper to that mode for good.
///
/// Late or repeated ids (a resent frame, a reordered packet) are reported, never fed on as new.
class FrameIdUnwrapper {
 public:
  enum class Verdict : uint8_t { kNext, kDuplicateOrLate, kInvalid };

  struct Result {
    Verdict verdict = Verdict::kInvalid;
    uint64_t sequence = 0;  ///< unwrapped 64-bit sequence (valid for kNext)
    uint64_t gap = 0;       ///< ids skipped just before this one (frames lost)
  };

  /// Feeds the next block id as it arrived.
  Result update(uint64_t block_id);

  void reset() { started_ = false; }
  uint64_t dropped() const { return dropped_; }
  uint64_t late() const { return late_; }

 private:
  static constexpr uint64_t kCycle16 = 65535;  // ids 1..65535
  bool started_ = false;
  bool extended_ = false;
  uint64_t last_id_ = 0;
  uint64_t sequence_ = 0;
  uint64_t dropped_ = 0;
  uint64_t late_ = 0;
};

}  // namespace hd::drivers
