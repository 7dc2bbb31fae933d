#include "sim/head_motion.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace hd::sim {

drivers::ScriptedMotion make_head_motion(const SceneHead& head) {
  if (!head.trajectory_csv.empty()) {
    return drivers::from_trajectory(drivers::Trajectory::load_csv(head.trajectory_csv));
  }
  struct Key {
    double t_s;
    Eigen::Vector3d p;
    Eigen::Quaterniond q;
  };
  std::vector<Key> keys;
  for (const HeadKeyframe& k : head.keyframes) {
    keys.push_back({k.t_s, k.position_m, Eigen::Quaterniond(rotation_from_ypr_deg(k.ypr_deg))});
  }
  const bool smooth = head.smooth;
  return [keys = std::move(keys), smooth](double t_s) {
    drivers::TrajectorySample out;
    out.t_s = t_s;
    if (keys.empty()) return out;
    if (t_s <= keys.front().t_s || keys.size() == 1) {
      out.position_m = keys.front().p;
      out.q = keys.front().q;
      return out;
    }
    if (t_s >= keys.back().t_s) {
      out.position_m = keys.back().p;
      out.q = keys.back().q;
      return out;
    }
    const auto next = std::upper_bound(keys.begin(), keys.end(), t_s,
                                       [](double t, const Key& k) { return t < k.t_s; });
    const Key& a = *(next - 1);
    const Key& b = *next;
    double u = (t_s - a.t_s) / (b.t_s - a.t_s);
    if (smooth) u = 0.5 * (1.0 - std::cos(M_PI * u));
    out.position_m = a.p + u * (b.p - a.p);
    out.q = a.q.slerp(u, b.q);
    return out;
  };
}

}  // namespace hd::sim
