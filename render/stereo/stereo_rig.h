#pragma once
// The operator's eyes: two virtual cameras for an HMD, one for a monitor.

#include <array>
#include <cmath>

#include "core/pinhole.h"
#include "core/pose.h"
#include "render/compositor/viewport.h"

namespace hd::render {

enum class Eye : uint8_t { kLeft = 0, kRight = 1 };

/// Each eye is the head pose offset by -IPD/2 (left) or +IPD/2 (right) along the head's x axis
/// (x right in camera axes), same orientation, with its own intrinsics p_o. Both eyes are drawn
/// side by side in one image: left at x = 0, right at x = left.width. A monitor is the one-eye
/// case: eye_count() == 1, the eye is the head pose itself with the left intrinsics.
struct StereoRig {
  bool stereo = true;
  double ipd_m = 0.064;
  std::array<core::Pinhole, 2> eye{};  ///< p_o per eye (left, right)

  static StereoRig monitor(const core::Pinhole& p_o) {
    StereoRig r;
    r.stereo = false;
    r.ipd_m = 0.0;
    r.eye = {p_o, p_o};
    return r;
  }

  int eye_count() const { return stereo ? 2 : 1; }

  core::Pose T_head_eye(int i) const {
    core::Pose p;
    if (stereo) p.t.x() = (i == 0 ? -0.5 : 0.5) * ipd_m;
    return p;
  }
  core::Pose T_world_eye(const core::Pose& T_world_head, int i) const {
    return T_world_head * T_head_eye(i);
  }

  Viewport viewport(int i) const {
    return {i == 0 ? 0 : eye[0].width, 0, eye[i].width, eye[i].height};
  }
  int output_width() const { return stereo ? eye[0].width + eye[1].width : eye[0].width; }
  int output_height() const {
    return stereo ? std::max(eye[0].height, eye[1].height) : eye[0].height;
  }

  /// The decision input for the frame: the worse eye's m, so both eyes always show the same
  /// variant. NaN counts as +inf (no usable video).
  static double worse_m(double m_left, double m_right) {
    if (std::isnan(m_left) || std::isnan(m_right)) return INFINITY;
    return std::max(m_left, m_right);
  }

  /// Intrinsics valid, positive finite IPD for stereo.
  bool valid() const {
    if (!eye[0].valid() || (stereo && !eye[1].valid())) return false;
    return !stereo || (std::isfinite(ipd_m) && ipd_m > 0.0 && ipd_m < 0.2);
  }
};

}  // namespace hd::render
