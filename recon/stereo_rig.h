#pragma once
// Two calibrated cameras seen as a stereo pair: their intrinsics p_c and workspace poses P_c, and
// the relative pose OpenCV's stereo functions take.

#include <opencv2/core.hpp>
#include <stdexcept>

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::recon {

/// A pair that cannot be reconstructed as given (bad intrinsics, no baseline, no common view).
/// The message says which camera and why.
class RigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Left and right camera as the calibration files give them: p_c in core's convention (pixel
/// centres at +0.5, distortion as calibrated) and P_c camera-to-world (t = camera centre, metres).
/// "Left" is the camera whose pixels the reconstruction is indexed by; it need not be on the left.
struct StereoRig {
  core::Pinhole left;
  core::Pinhole right;
  core::Pose T_world_left;
  core::Pose T_world_right;

  /// The right camera seen from the left one: X_right = R * X_left + T, the (R, T) of
  /// cv::stereoCalibrate / cv::stereoRectify.
  cv::Matx33d R_right_left() const;
  cv::Vec3d T_right_left() const;

  double baseline_m() const { return (T_world_right.t - T_world_left.t).norm(); }

  /// Throws RigError unless both pinholes are valid, both poses are rotations and the cameras are
  /// at least `min_baseline_m` apart.
  void check(double min_baseline_m = 1e-4) const;
};

}  // namespace hd::recon
