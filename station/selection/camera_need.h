#pragma once
// Which cameras the station needs at full rate (bandwidth follows the view, issue 12 item 5):
// from m of every camera at the predicted pose, with a hold time so a camera near the threshold
// does not flap.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace hd::station {

struct CameraNeedParams {
  double m_t = 40.0;     ///< the transition's threshold on m (core::TransitionParams::m_t)
  double margin = 20.0;  ///< wanted while m < m_t + margin: it may be shown soon
  double hold_s = 2.0;   ///< not needed only after being unwanted this long
};

/// Per frame: update(m per camera, chosen camera, time). A camera is *wanted* in a frame when its
/// m < m_t + margin, or it is the chosen camera, or the runner-up (lowest m of the others);
/// it is *needed* while wanted or wanted within the last hold_s. Before the first update every
/// camera is needed (the safe default: full rate). m must be the geometric measure at the
/// predicted pose, not the age-extended one: a camera sent at a low rate has old video, and its
/// age must not be what keeps it at the low rate. +inf / NaN m is never wanted by the threshold.
/// No allocation after construction.
class CameraNeedPolicy {
 public:
  CameraNeedPolicy(std::size_t cameras, CameraNeedParams params);
  void update(std::span<const double> m, int chosen, int64_t now_ns);
  /// Camera i is needed whatever the view: e.g. a stereo pair the model updater reconstructs
  /// from, which needs frames of one exposure from both cameras.
  void keep(std::size_t i) { kept_[i] = 1; }
  bool needed(std::size_t i) const { return needed_[i] != 0; }
  std::size_t size() const { return needed_.size(); }
  /// Changes of any camera's need since construction (flaps show here).
  uint64_t changes() const { return changes_; }
  /// Of which camera i's.
  uint64_t changes(std::size_t i) const { return camera_changes_[i]; }

 private:
  CameraNeedParams params_;
  std::vector<int64_t> last_wanted_ns_;
  std::vector<uint8_t> needed_;
  std::vector<uint8_t> kept_;
  bool started_ = false;
  uint64_t changes_ = 0;
  std::vector<uint64_t> camera_changes_;
};

}  // namespace hd::station
