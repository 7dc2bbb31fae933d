#pragma once
// The fitted-plane video view's d: the plane z_c = d laid through the model where the eye sees
// the camera's frame, chosen every frame and followed smoothly so the picture does not swim.

#include <vector>

#include "core/pinhole.h"
#include "core/pixel_rect.h"
#include "core/pose.h"
#include "render/compositor/camera_depth_map.h"
#include "render/compositor/synthetic_scene.h"

namespace hd::station {

/// Per camera. Each frame: target = the median camera-frame depth z_c of the model surfaces the
/// camera sees inside `region` (the part of its frame the eye sees, real pixels), then
/// d += (target - d)(1 - exp(-dt / kTimeConstant_s)). The median, not the mean, so a small near
/// object in a view of a wall leaves d on the wall (E is then small on most of what is shown);
/// the lag, because d jumps where the region crosses a depth edge and a plane that jumps makes the
/// video jump. The depth map is drawn at 1/kMapScale of the frame's size, only when the model or
/// the camera changes (render::CameraDepthMap). Sized in the constructor; update() allocates
/// only when the model grows (the map's rasteriser), never per frame.
class FittedPlane {
 public:
  /// 1/8 of 640 x 480 is 80 x 60 = 4800 depth samples: a median to well under a percent of the
  /// depth range, and a map that costs ~0.1 ms to draw.
  static constexpr int kMapScale = 8;
  /// About two tracker-to-display latencies: the head crosses a depth edge in a few hundred
  /// milliseconds, and d follows it within ~3 tau = 0.6 s while no frame moves it by more than
  /// 1 - exp(-dt/tau) of the jump (5.4 % at 90 Hz).
  static constexpr double kTimeConstant_s = 0.2;

  /// `camera`: the real camera's pinhole (frame size); `d_m`: where d starts (the camera's d).
  FittedPlane(const core::Pinhole& camera, double d_m);

  /// A new calibration (a network camera's streamed one): the map follows its intrinsics;
  /// allocates only when the map grows. d stays.
  void set_camera(const core::Pinhole& camera);

  /// d for this frame. `region` nullptr: the whole frame. No model surface in the region (or no
  /// scene): d stays. The first update with a surface takes the target directly; after that
  /// dt_s <= 0 or NaN holds d.
  double update(const render::SyntheticScene* scene, const core::Pose& T_world_cam,
                const core::PixelRect* region, double dt_s);
  double d_m() const { return d_m_; }
  /// The last target (the unsmoothed median; NaN before the first with a surface).
  double target_m() const { return target_m_; }

 private:
  core::Pinhole map_camera_;
  core::Pinhole camera_;
  render::CameraDepthMap map_;
  std::vector<float> depths_;  ///< the region's depths, sized to the map once
  double d_m_;
  double target_m_;
  bool started_ = false;
};

}  // namespace hd::station
