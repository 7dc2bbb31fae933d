#pragma once
// One simulated camera's picture maker: the scene rendered at the exposure time by a CpuCompositor
// this renderer owns (so each camera thread has its own), with the listed frame effects. Effects
// not listed are never constructed; with none, a frame is one render handed over by swapping
// buffers (no copy).

#include <memory>
#include <optional>
#include <vector>

#include "drivers/frame.h"
#include "render/compositor/cpu_compositor.h"
#include "render/compositor/synthetic_scene.h"
#include "sim/pixel_effects.h"
#include "sim/scene/scene.h"

namespace hd::sim {

class Simulation;

class SimCameraRenderer {
 public:
  /// Allocates everything a frame needs (call outside the frame path).
  SimCameraRenderer(const Simulation& sim, std::size_t camera_index);

  /// Fills `frame` (allocated to the camera size if it is not) with the view at scene time t_s,
  /// the start of the exposure. frame.sequence must be set (it seeds the noise).
  void render(drivers::Frame& frame, double t_s);

  /// The camera as rendered: its intrinsics without distortion.
  const core::Pinhole& ideal_camera() const { return ideal_; }

 private:
  void draw_rows(double t_s, int row_begin, int row_end);

  const Simulation& sim_;
  core::Pinhole ideal_;
  core::Pose T_world_cam_;
  render::SyntheticScene scene_;  ///< the model copy whose objects are moved to each render's time
  render::CpuCompositor compositor_{1};
  render::ImageRgba8 image_;
  std::vector<uint16_t> accum_;  ///< motion blur sum
  std::optional<MotionBlurEffect> blur_;
  std::optional<RollingShutterEffect> rolling_;
  std::unique_ptr<LensDistorter> distorter_;
  std::optional<ExposureLut> exposure_;
  std::optional<SensorNoise> noise_;
};

}  // namespace hd::sim
