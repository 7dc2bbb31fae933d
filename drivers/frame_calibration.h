#pragma once
// The calibration a frame was taken with, when its source says (a network camera whose sender
// streams p_c and P_c, docs/network.md); otherwise the station's calibration file applies.

#include <cstdint>

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::drivers {

/// p_c in core::Pinhole's convention (pixel centres at +0.5) with its distortion as calibrated,
/// P_c camera-to-world (X_world = R X_cam + t). `revision` changes whenever either changes (a
/// recalibration, or a camera that moves); frames with the same revision share one calibration.
/// Fixed size: copied with every frame, never allocates.
struct FrameCalibration {
  bool present = false;  ///< false: the source sent none (a file's calibration applies)
  uint32_t revision = 0;
  core::Pinhole p_c;
  core::Pose T_world_cam;
};

}  // namespace hd::drivers
