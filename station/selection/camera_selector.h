#pragma once
// Which camera's video to show: the lowest m wins, with hysteresis so the view does not flicker.

#include <cstddef>
#include <span>

namespace hd::station {

struct SelectionParams {
  /// Another camera must be better by this fraction of the current m (m_other < (1 - margin) *
  /// m_current) ...
  double margin = 0.2;
  /// ... continuously for this long before the view switches to it.
  double dwell_s = 0.25;
};

/// Per frame: update(m per camera, dt) -> index of the camera to show, or -1 when no camera has
/// a finite m. A current camera whose m became +inf/NaN is left at once (nothing to hold on to).
/// No allocation: the span is read, nothing stored but indices and a timer.
class CameraSelector {
 public:
  explicit CameraSelector(SelectionParams params = {}) : params_(params) {}
  int update(std::span<const double> m, double dt_s);
  int current() const { return current_; }
  unsigned long switches() const { return switches_; }
  void reset() {
    current_ = -1;
    better_for_s_ = 0.0;
  }

 private:
  SelectionParams params_;
  int current_ = -1;
  double better_for_s_ = 0.0;
  unsigned long switches_ = 0;
};

}  // namespace hd::station
