#pragma once
// The view transition policy (paper VII): which variant to show and with what video weight.

namespace hd::core {

enum class Variant { kVideo, kHybrid, kSynthetic };
enum class TransitionMode { kAbrupt, kGlobalBlend, kPerPixel };

struct TransitionParams {
  TransitionMode mode = TransitionMode::kPerPixel;
  double m_t = 40;
  double eps = 10;
  double hysteresis = 5;          ///< abrupt: switch to synthetic above m_t+h, back below m_t-h
  double time_constant_s = 0.15;  ///< first-order smoothing of w_video; 0 = none
};

struct TransitionState {
  Variant variant;
  double w_video;  ///< global weight of the video; per-pixel mode feeds it to the pixel rule
  double kappa;    ///< 1 - w_video, the paper's border width
};

/// Below half an 8-bit level the global blend cannot change an output value: out = round(s + a(v -
/// s)) with |a (v - s)| < 255 / 512 < 0.5 rounds to s. In per-pixel mode the border band it drops
/// is kappa = 1/512 of the frame (1.25 px of 640). With the old 1e-6 a 0.15 s lag stayed "hybrid"
/// ~2 s after the picture was pure.
inline constexpr double kTransitionSnap = 1.0 / 512.0;

/// Per-frame transition. Abrupt: w_video is 1 or 0 with hysteresis, never smoothed (an abrupt
/// switch is the point of that mode). Blend modes: target = video_weight(m, m_t, eps), followed by
/// a first-order lag w += (target - w)(1 - exp(-dt/tau)) -- the paper's "time-based blending";
/// the lag snaps to the target within kTransitionSnap so the variant really reaches video or
/// synthetic as soon as the picture is (no frame marked "hybrid" that shows one source only).
/// NaN or +inf m counts as +inf (synthetic). NaN or negative dt holds the weight. The first
/// update after construction/reset takes the target directly. No allocation, no clock.
class Transition {
 public:
  explicit Transition(TransitionParams p);
  TransitionState update(double m, double dt_s) { return update(m, dt_s, 1.0); }
  /// The same with the video weight held at or below `w_cap` (core/video_age.h's age cap):
  /// the smoothed weight itself is lowered, so video that comes back fades in from there. The
  /// abrupt mode shows video only with w_cap >= 1. w_cap >= 1 (or NaN) changes nothing.
  TransitionState update(double m, double dt_s, double w_cap);
  void reset();
  const TransitionParams& params() const { return p_; }

 private:
  TransitionParams p_;
  bool started_ = false;
  bool abrupt_video_ = true;
  double w_ = 0.0;
};

}  // namespace hd::core
