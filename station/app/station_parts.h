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
#include "station/app/run_options.h"
#include "station/app/startup_report.h"
#include "station/app/station_config.h"
#include "station/frame/station_frame.h"
#include "station/model/model_updater.h"
#include "station/tracking/aligned_pose_source.h"
#include "station/video/camera_pipeline.h"

namespace hd::station {

/// Owns every device and stage of one run. Members are declared in dependency order so they are
/// destroyed consumers first (updater, then pose alignment, pipelines, devices, simulator).
struct StationParts {
  StartupReport report;
  std::string source_kind;  ///< "scene" or "config"
  std::string source_file;

  // Owned devices (a scene's are inside `simulation`).
  std::unique_ptr<sim::Simulation> simulation;
  std::vector<std::unique_ptr<drivers::CameraSource>> devices;
  std::unique_ptr<drivers::PoseSource> tracker;

  std::vector<std::unique_ptr<station::CameraPipeline>> pipelines;
  std::unique_ptr<station::AlignedPoseSource> head;
  std::vector<drivers::CalibratedCamera> cameras;  ///< sources = pipelines
  std::vector<std::string> camera_names;
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
  /// Cameras the loop waits for before its first frame (the network's), and for how long.
  std::vector<std::size_t> awaited_cameras;
  double camera_wait_s = 0.0;

  StationParts() = default;
  StationParts(const StationParts&) = delete;
  StationParts& operator=(const StationParts&) = delete;
  ~StationParts();

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

void configure_frame(StationParts& p, DisplayConfig display, core::TransitionParams transition,
                     core::MarkingParams marking, const core::WorkspaceBox& workspace,
                     const std::string& predictor, const RunOptions& options);

/// From a scene file (already loaded): "sim:<name>" cameras and "sim:head", the scene's model,
/// a model updater when the scene lists model_staleness. Opens the devices; anything that fails
/// is in the report.
std::unique_ptr<StationParts> assemble_from_scene(sim::Scene scene, const RunOptions& options);

/// From station.yaml (already loaded): cameras by driver id through pipelines with their
/// calibration, the tracker, the model geometry of the scene file it names (or none). Opens every
/// device; a missing required one makes report.fatal().
std::unique_ptr<StationParts> assemble_from_config(const StationConfig& config,
                                                   const RunOptions& options);

}  // namespace hd::station
