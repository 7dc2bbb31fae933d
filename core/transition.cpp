#include "core/transition.h"

#include <cmath>
#include <limits>

#include "core/blend_weights.h"

namespace hd::core {

Transition::Transition(TransitionParams p) : p_(p) {}

void Transition::reset() {
  started_ = false;
  abrupt_video_ = true;
  w_ = 0.0;
}

TransitionState Transition::update(double m, double dt_s, double w_cap) {
  if (std::isnan(m)) m = std::numeric_limits<double>::infinity();
  const double h = std::isfinite(p_.hysteresis) && p_.hysteresis > 0.0 ? p_.hysteresis : 0.0;
  if (p_.mode == TransitionMode::kAbrupt) {
    if (std::isnan(p_.m_t)) {
      abrupt_video_ = false;
    } else if (!started_) {
      abrupt_video_ = m <= p_.m_t;
    } else if (abrupt_video_ && m > p_.m_t + h) {
      abrupt_video_ = false;
    } else if (!abrupt_video_ && m < p_.m_t - h) {
      abrupt_video_ = true;
    }
    started_ = true;
    w_ = abrupt_video_ && !(w_cap < 1.0) ? 1.0 : 0.0;
  } else {
    const double target = video_weight(m, p_.m_t, p_.eps);
    const double tau = p_.time_constant_s;
    if (!started_ || !(tau > 0.0) || std::isnan(tau)) {
      w_ = target;
    } else if (dt_s > 0.0) {  // false for NaN and negative dt: hold
      const double alpha = 1.0 - std::exp(-dt_s / tau);
      w_ += (target - w_) * alpha;
      if (std::abs(target - w_) < kTransitionSnap) w_ = target;
    }
    if (w_cap < w_) w_ = w_cap <= kTransitionSnap ? 0.0 : w_cap;  // false for NaN
    started_ = true;
  }
  const Variant v =
      w_ >= 1.0 ? Variant::kVideo : (w_ <= 0.0 ? Variant::kSynthetic : Variant::kHybrid);
  return {v, w_, 1.0 - w_};
}

}  // namespace hd::core
