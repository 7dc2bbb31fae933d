#pragma once
// How far apart two calibrations of one camera put its pixels: what the station reports when a
// network camera's streamed calibration differs from its calibration file (docs/network.md).

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::station {

/// The largest distance, in pixels of the undistorted image, between where calibration `a` and
/// calibration `b` put the same world point, over a 9 x 7 grid of raw (distorted) pixels across
/// a's image: each grid pixel is undistorted with a's p_c and placed depth_m in front of a's
/// camera (P_a), then projected with b's pose and pinhole and compared with the same raw pixel
/// undistorted with b's p_c. 0 for identical calibrations; a principal point moved by s px gives
/// s; a camera moved sideways by dx gives f dx / depth_m. +inf when either is not a valid
/// calibration or the point falls behind b.
double calibration_difference_px(const core::Pinhole& a, const core::Pose& P_a,
                                 const core::Pinhole& b, const core::Pose& P_b, double depth_m);

}  // namespace hd::station
