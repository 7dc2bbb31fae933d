#pragma once
// A camera as the station shows it: its device and the calibration that places its pixels in the
// workspace (p_c, P_c) with the plane distance d of its video quad.

#include "core/pinhole.h"
#include "core/pose.h"
#include "core/video_view.h"
#include "drivers/camera_source.h"

namespace hd::drivers {

/// `source` is not owned. p_c uses core::Pinhole's convention (pixel centres at +0.5); P_c is
/// camera-to-world (X_world = R X_cam + t, t the camera centre).
struct CalibratedCamera {
  CameraSource* source = nullptr;
  core::Pinhole p_c;
  core::Pose T_world_real;
  double d_m = 1.0;  ///< distance of the video quad's plane along the camera's z axis
  /// Video older than this at the display time is not shown as live (core/video_age.h);
  /// <= 0: core::default_max_video_age_s of an unknown rate (100 ms).
  double max_video_age_s = 0.0;
  core::VideoView video_view = core::VideoView::kPlane;  ///< plane at d_m, fitted, or model depth
};

}  // namespace hd::drivers
