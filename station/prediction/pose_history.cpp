#include "station/prediction/pose_history.h"

#include <cmath>

namespace hd::station {

int PoseHistory::pull(Ring& ring, PosePredictor* predictor) {
  int n = 0;
  drivers::PoseSample s;
  while (ring.pop(s)) {
    if (add(s, predictor)) ++n;
  }
  return n;
}

bool PoseHistory::add(const drivers::PoseSample& s, PosePredictor* predictor) {
  auto reject = [this](std::string_view why) {
    ++rejected_;
    last_rejection_ = why;
    return false;
  };
  if (!s.T_tracker_head.valid(1e-4))
    return reject("pose sample: rotation not orthonormal or not finite");
  if (s.has_angular_velocity && !s.angular_velocity_rad_s.allFinite())
    return reject("pose sample: angular_velocity_rad_s not finite");
  if (seen_any_ && s.reset_counter != reset_counter_) {
    // The tracker re-zeroed its frame: old samples describe another frame, velocities across the
    // jump would be nonsense.
    count_ = 0;
    ++resets_;
    if (predictor) predictor->reset();
  }
  if (count_ > 0 && s.host_timestamp_ns <= newest().t_ns)
    return reject("pose sample: host_timestamp_ns not after the previous sample");
  seen_any_ = true;
  reset_counter_ = s.reset_counter;

  HeadSample& h = items_[head_];
  h.t_ns = s.host_timestamp_ns;
  h.q_world_head = Eigen::Quaterniond(s.T_tracker_head.R).normalized();
  h.p_world_m = s.T_tracker_head.t;
  h.omega_head_rad_s = s.has_angular_velocity ? s.angular_velocity_rad_s : Eigen::Vector3d::Zero();
  h.has_omega = s.has_angular_velocity;
  h.has_position = s.has_position;
  head_ = (head_ + 1) % kCapacity;
  if (count_ < kCapacity) ++count_;
  ++accepted_;
  if (predictor) predictor->observe(h);
  return true;
}

}  // namespace hd::station
