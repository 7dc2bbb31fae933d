#pragma once
// The assembled station: devices -> camera pipelines (undistortion, model tee) -> aligned head
// pose -> model updater -> StationFrame's configuration, built from a scene file (simulated
// devices) or from station.yaml (real devices), with the startup report of what was found.

#include <memory>
#include <string>
#include <vector>

#include "drivers/camera_source.h"
#include "drivers/pose_source.h"
#include "render/compositor/synthetic_scene.h"
#include "sim/scene/scene.h"
#include "sim/simulation.h"
#include "sim/stepped_camera.h"
#include "sim/stepped_head.h"
#include "station/app/run_options.h"
#include "station/app/startup_report.h"
#include "station/app/station_camera.h"
#include "station/app/station_config.h"
#include "station/frame/station_frame.h"
#include "station/model/model_updater.h"
#include "station/tracking/aligned_pose_source.h"
#include "station/video/camera_pipeline.h"

namespace hd::station {

/// Owns every device and stage of one run. Members are declared in dependency order so they are
/// destroyed consumers first (updater, then pose alignment and tracker, cameras, simulator).
struct StationParts {
  StartupReport report;
  std::string source_kind;  ///< "scene" or "config"
  std::string source_file;

  std::unique_ptr<sim::Simulation> simulation;  ///< a scene's devices live in it
  /// A run on the scene's clock (`hybrid-station score`): the scene's cameras and head stepped
  /// by the run instead of the simulation's threads, scene t = 0 at host time epoch_ns. The
  /// pipelines, the head's alignment and the model updater are then driven by the run too
  /// (start() starts only these devices).
  struct SteppedDevices {
    int64_t epoch_ns = 0;
    std::vector<std::unique_ptr<sim::SteppedCamera>> cameras;  ///< by scene camera index
    std::unique_ptr<sim::SteppedHead> head;
  };
  std::unique_ptr<SteppedDevices> stepped;
  /// Every camera that opened, in the file's order: device, pipeline, calibration, link.
  std::vector<StationCamera> cameras;
  std::unique_ptr<drivers::PoseSource> tracker;
  std::unique_ptr<station::AlignedPoseSource> head;
  render::SyntheticScene model;  ///< the a-priori model (drawn as is without an updater)
  std::unique_ptr<render::LoopClock> updater_clock;
  std::unique_ptr<station::ModelUpdater> updater;

  station::StationFrameConfig frame_config;
  double rate_hz = 90.0;
  double scanout_ms = 2.0;
  std::string predictor = "kalman";
  int monitor = -1;              ///< fullscreen monitor for a windowed GL run, -1 = a window
  double default_seconds = 0.0;  ///< run length when neither --frames nor --seconds is given
  /// Scene t = 0 on CLOCK_MONOTONIC when fixed from outside (--scene-epoch), else 0: the run
  /// then waits for it and, without --frames/--seconds, ends at t = default_seconds.
  int64_t scene_epoch_ns = 0;
  std::string scene_epoch_text;  ///< as given
  std::string cameras_from;      ///< --cameras-from as given ("" simulated here)
  double camera_wait_s = 0.0;    ///< how long the loop waits for its awaited cameras

  StationParts() = default;
  StationParts(const StationParts&) = delete;
  StationParts& operator=(const StationParts&) = delete;
  ~StationParts();

  /// What StationFrame measures and draws: each camera's calibrated camera, in order.
  std::vector<drivers::CalibratedCamera> calibrated_cameras() const;
  /// Each camera's name, in order (frames.csv's camera column).
  std::vector<std::string> camera_names() const;
  /// The index of the camera the scene or station.yaml calls `name`, or -1.
  int camera_index(const std::string& name) const;

  /// Starts pipelines (and so their devices), the head and the model updater.
  void start();
  /// Stops in reverse order; idempotent.
  void stop();

 private:
  bool started_ = false;
};

/// Fills p.frame_config, rate, scan-out, predictor and monitor from the file's values with the
/// command line's overrides applied (an option given wins), and notes them in the report.
/// A stereo pair as a scene file or station.yaml gives it, as the model updater takes it: cameras
/// `left` / `right` by index into the updater's cameras, vertices kept inside `workspace`.
station::ModelStereoPair model_stereo_pair(const sim::SceneStereoPair& pair, std::size_t left,
                                           std::size_t right, const core::WorkspaceBox& workspace);

/// The model updater over every camera of `p`: re-textures p.model from their frames (with
/// uc's period and delay) and reconstructs the stereo pairs, matched to cameras by name (a pair
/// whose camera did not open, or that cannot be one, is reported and left out). Returns the
/// pairs in use ("cam0+cam0r, ..."; "" none).
std::string add_model_updater(StationParts& p, station::ModelUpdaterConfig uc,
                              const std::vector<sim::SceneStereoPair>& stereo,
                              const core::WorkspaceBox& workspace);

void configure_frame(StationParts& p, DisplayConfig display, core::TransitionParams transition,
                     core::MarkingParams marking, const core::WorkspaceBox& workspace,
                     const std::string& predictor, const RunOptions& options);

/// How a scene's devices run: on their threads against CLOCK_MONOTONIC (`run`), or stepped by
/// the caller on the scene's clock (`score`: StationParts::stepped).
enum class SceneDevices { kThreaded, kStepped };

/// From a scene file (already loaded): "sim:<name>" cameras and "sim:head", the scene's model,
/// a model updater when the scene lists model_staleness. Opens the devices; anything that fails
/// is in the report.
std::unique_ptr<StationParts> assemble_from_scene(sim::Scene scene, const RunOptions& options,
                                                  SceneDevices devices = SceneDevices::kThreaded);

/// From station.yaml (already loaded): cameras by driver id through pipelines with their
/// calibration, the tracker, the model geometry of the scene file it names (or none). Opens every
/// device; a missing required one makes report.fatal().
std::unique_ptr<StationParts> assemble_from_config(const StationConfig& config,
                                                   const RunOptions& options);

}  // namespace hd::station
