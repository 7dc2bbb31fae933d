#pragma once
// The calibrations a network camera's sender streamed (rtp_calibration.h), kept for the frames
// that name them by revision, with the counts of what was refused.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>

#include "drivers/frame_calibration.h"
#include "drivers/rtp/rtp_calibration.h"

namespace hd::drivers {

/// The newest kSize accepted calibrations, newest first. A frame is published with the
/// calibration of its packets' camera-state revision, which may be a few frames older than the
/// newest element (frames in flight through the decoder), hence more than one.
///
/// Threads: add() and refuse() are the depayloader's, lookup(), fits() and count_published() the
/// appsink's, newest() and counts() any. A calibration is added before the packets naming its
/// revision reach the frame's slot (RtpFrameStamper), so a frame that names one finds it.
/// Nothing allocates: calibrations are fixed size.
class RtpCalibrationCache {
 public:
  static constexpr std::size_t kSize = 4;

  struct Counts {
    std::array<uint64_t, static_cast<std::size_t>(CalibrationError::kCount)> refused{};
    uint64_t refused_total = 0;
    uint64_t received = 0;                 ///< elements accepted (add())
    uint64_t frames_with_calibration = 0;  ///< count_published()
    uint64_t size_mismatch = 0;            ///< fits() said no
  };

  /// An accepted element: becomes the newest (replacing the newest when it has its revision).
  void add(const StreamCalibration& c);
  /// A refused element (ignored), by reason; kNone counts nothing.
  void refuse(CalibrationError e);
  /// The held calibration of `revision` (present = false when none is held).
  FrameCalibration lookup(uint32_t revision) const;
  /// Whether a frame of width x height may carry `c`: true without one; false (counted) when its
  /// image size is another (a frame is never shown with the wrong calibration).
  bool fits(const FrameCalibration& c, int width, int height);
  /// A frame was published; `calibrated`: it carried a calibration (counted).
  void count_published(bool calibrated);

  std::optional<StreamCalibration> newest() const;
  Counts counts() const;

 private:
  mutable std::mutex mutex_;
  std::array<std::optional<StreamCalibration>, kSize> held_{};
  std::array<std::atomic<uint64_t>, static_cast<std::size_t>(CalibrationError::kCount)> refused_{};
  std::atomic<uint64_t> received_{0}, frames_with_calibration_{0}, size_mismatch_{0};
};

}  // namespace hd::drivers
