#pragma once
// The simulator behind the station's mock devices: a Scene becomes MockCameras ("sim:<name>")
// whose frames are the scene rendered at each frame's exposure time (moving objects placed at that
// time) with the listed frame effects, and a MockPoseSource ("sim:head") replaying the head motion
// with the listed tracker effects. The station sees them only as CameraSource / PoseSource.
//
// Effects not listed in the scene are not constructed: with an empty list a frame is exactly one
// CpuCompositor render of the camera's view, copied into the frame.
//
// Time: every device shares one epoch (the first start() of any of them); scene time t_s is
// (host_ns - epoch_ns) / 1e9. Cameras expose on the grid epoch + k / rate_hz.

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "drivers/calibrated_camera.h"
#include "drivers/camera_source.h"
#include "drivers/frame.h"
#include "drivers/mock/mock_camera.h"
#include "drivers/mock/mock_pose_source.h"
#include "drivers/pose_source.h"
#include "render/compositor/synthetic_scene.h"
#include "sim/scene/scene.h"

namespace hd::sim {

/// When frame `sequence` of a camera is exposed and delivered (deterministic, seeded).
struct SimFrameTiming {
  int64_t exposure_offset_ns = 0;  ///< exposure time - epoch
  int64_t delivery_delay_ns = 0;   ///< camera delay + network delay (0 without those effects)
  bool dropped = false;            ///< dropped_frames: never delivered (a sequence gap)
};

class SimCameraRenderer;  // sim/sim_camera_renderer.h
class SimEpoch;           // sim/sim_epoch.h

class Simulation {
 public:
  /// Builds textures, meshes and devices (not started). Throws config::ConfigError (a texture file
  /// that cannot be read) or std::invalid_argument for a scene load_scene() would not produce.
  explicit Simulation(Scene scene);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  const Scene& scene() const { return scene_; }

  // ---- devices (owned here; the station opens/starts/stops them, or call start()/stop()) ----
  std::size_t camera_count() const { return cameras_.size(); }
  drivers::MockCamera& camera(std::size_t i) { return *cameras_[i]; }
  drivers::MockPoseSource& head() { return *head_; }
  void start();  ///< all cameras and the head
  void stop();

  /// The calibrated cameras as the station needs them: source, p_c (with the distortion
  /// coefficients only when lens_distortion is listed, i.e. only when frames are distorted),
  /// P_c and d. Pointers stay valid for the Simulation's lifetime.
  std::vector<drivers::CalibratedCamera> station_cameras();

  // ---- the a-priori model ----
  /// Static geometry followed by the moving objects placed at t = 0.
  const render::SyntheticScene& model() const { return model_; }
  /// The static geometry only (the scene's `geometry:`), without the moving objects: what a
  /// station knows a priori when moved objects are reconstructed (MovedObjects::kReconstructed).
  render::SyntheticScene static_model() const;
  /// Moves the moving objects' meshes of `model` (a copy of model()) to where they are at t_s
  /// and bumps its revision. Rewrites vertex positions only: no allocation.
  void place_objects(render::SyntheticScene& model, double t_s) const;
  /// Listed model_staleness (refresh period and delay), for the station's model updater.
  const std::optional<ModelStalenessEffect>& model_staleness() const {
    return scene_.effects.model_staleness;
  }

  // ---- time ----
  /// Host time of scene t = 0; 0 before any device started (or set_epoch_ns).
  int64_t epoch_ns() const;
  /// Fixes scene t = 0 at host time `host_ns` (CLOCK_MONOTONIC; may lie ahead: the devices then
  /// wait for it) before any device starts, so that two processes simulating parts of one scene
  /// (hybrid-remote's cameras, the station's head) share its clock (sim/scene_epoch.h). False when
  /// the epoch was already set to another instant (a device had started).
  bool set_epoch_ns(int64_t host_ns);
  double scene_time_s(int64_t host_ns) const;

  // ---- deterministic, offline (tests, benchmarks; independent of the running devices) ----
  SimFrameTiming frame_timing(std::size_t camera, uint64_t sequence) const;
  /// Renders frame `sequence` of `camera` (at its exposure time, with the frame effects) into
  /// `frame` (allocated to the camera's size if needed). Uses a renderer of its own, not the
  /// running device's.
  void render_frame(std::size_t camera, uint64_t sequence, drivers::Frame& frame);
  /// The head sample the tracker publishes at scene time t_s (sequence: the noise draw).
  drivers::PoseSample head_sample(double t_s, uint64_t sequence) const;

 private:
  Scene scene_;
  render::SyntheticScene model_;
  std::vector<std::pair<std::size_t, std::size_t>> object_meshes_;   ///< [first, end) per object
  std::vector<std::vector<Eigen::Vector3f>> object_local_vertices_;  ///< per object mesh
  std::shared_ptr<SimEpoch> epoch_;
  std::vector<std::unique_ptr<SimCameraRenderer>> device_renderers_;   ///< one per camera thread
  std::vector<std::unique_ptr<SimCameraRenderer>> offline_renderers_;  ///< render_frame()
  std::vector<std::unique_ptr<drivers::MockCamera>> cameras_;
  std::unique_ptr<drivers::MockPoseSource> head_;
};

}  // namespace hd::sim
