#pragma once
// One frame of the station, as the frame loop runs it: late-latched predicted pose, m for every
// camera and eye, camera choice, transition, compositing, guidance, latency record.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/marking.h"
#include "core/transition.h"
#include "core/view_measure.h"
#include "core/workspace_box.h"
#include "drivers/calibrated_camera.h"
#include "drivers/camera_source.h"
#include "drivers/pose_source.h"
#include "render/compositor/compositor.h"
#include "render/latency/latency_recorder.h"
#include "render/lens/lens_warp.h"
#include "render/loop/frame_loop.h"
#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"
#include "render/stereo/stereo_rig.h"
#include "station/prediction/pose_history.h"
#include "station/selection/camera_selector.h"

namespace hd::station {

class ModelUpdater;

struct StationFrameConfig {
  render::StereoRig rig;
  core::Pose T_world_tracker;  ///< where the tracker's frame sits in the workspace
  core::WorkspaceBox workspace;
  double near_m = 0.05;
  core::TransitionParams transition;
  SelectionParams selection;
  core::MarkingParams marking;
  bool draw_guidance = true;
  std::size_t max_rows = 100'000;  ///< per-frame rows kept (preallocated)
  /// The HMD's lens (null: none, a monitor or the neutral profile): the eyes are pre-distorted
  /// into the panel's picture, which is what image() and the display show.
  std::shared_ptr<const render::lens::LensWarp> lens;

  /// The picture the station shows: the panel with a lens, else the eyes side by side.
  int picture_width() const { return lens ? lens->panel_width() : rig.output_width(); }
  int picture_height() const { return lens ? lens->panel_height() : rig.output_height(); }
};

/// What was decided in one frame (one CSV row of the run command).
struct FrameRow {
  uint64_t frame = 0;
  double m = 0.0;  ///< chosen camera's worse-eye m (+inf: none usable)
  double w_video = 0.0;
  int camera = -1;
  core::Variant variant = core::Variant::kSynthetic;
  bool guidance = false;
  double guidance_distance_m = 0.0;
  double guidance_dir_x = 0.0, guidance_dir_y = 0.0;
  double head_x_m = 0.0, head_y_m = 0.0, head_z_m = 0.0;  ///< predicted head position
};

/// Per-frame work. Everything is sized in the constructor; tick() does not allocate (shown by
/// loop_no_allocation_test), lock or throw.
class StationFrame final : public render::FrameWork {
 public:
  StationFrame(StationFrameConfig config, std::span<const drivers::CalibratedCamera> cameras,
               drivers::PoseSource& pose, PosePredictor& predictor, render::Compositor& compositor,
               const render::SyntheticScene* scene, render::LoopClock& clock,
               render::LatencyRecorder& latency);

  void tick(const render::FrameTiming& timing) override;

  /// Draws the updater's newest published model (fetched each tick, no allocation) instead of
  /// the fixed `scene`, and records its capture time as the latency record's model_capture_ns.
  /// nullptr: back to the fixed scene. Call before the loop runs; the updater must outlive it.
  void set_model_updater(ModelUpdater* updater);

  /// The HUD line drawn at the top of eye 0 (e.g. LatencyRecorder::hud_line()); "" hides it.
  /// Renders the text with OpenCV, which may allocate: call it outside tick(), e.g. every ~0.5 s.
  void set_hud_text(std::string_view text) { hud_.set_text(text); }
  const render::HudStrip& hud() const { return hud_; }

  /// What is shown: the panel's picture with a lens, else the eyes' (eyes_image()).
  const render::ImageRgba8& image() const { return config_.lens ? panel_ : out_; }
  const render::ImageRgba8& eyes_image() const { return out_; }
  const std::vector<FrameRow>& rows() const { return rows_; }
  uint64_t rows_dropped() const { return rows_dropped_; }
  /// The newest frame's row, kept even when rows() is full (max_rows = 0 keeps none: a caller
  /// logging frames itself, e.g. a long run, reads this after each tick).
  const FrameRow& last_row() const { return last_row_; }
  const PoseHistory& pose_history() const { return history_; }
  const CameraSelector& selector() const { return selector_; }
  /// Frames in which each camera showed a new frame (index = camera).
  const std::vector<uint64_t>& frames_fetched() const { return fetched_; }

 private:
  StationFrameConfig config_;
  std::vector<drivers::CalibratedCamera> cameras_;
  std::vector<render::GuidanceCamera> guidance_cameras_;
  drivers::PoseSource& pose_;
  PosePredictor& predictor_;
  render::Compositor& compositor_;
  const render::SyntheticScene* scene_;
  ModelUpdater* model_ = nullptr;
  render::LoopClock& clock_;
  render::LatencyRecorder& latency_;
  core::Transition transition_;
  CameraSelector selector_;
  PoseHistory history_;
  render::ImageRgba8 out_;
  render::ImageRgba8 panel_;  ///< allocated with a lens only
  render::HudStrip hud_;
  render::Viewport hud_viewport_{};  ///< with a lens: eye 0's visible part, in the eyes' picture
  std::vector<double> m_camera_;     ///< worse-eye m per camera
  std::vector<core::ViewMeasure> measure_;  ///< [camera * 2 + eye]
  std::vector<uint8_t> has_frame_;
  std::vector<uint64_t> fetched_;
  std::vector<FrameRow> rows_;
  uint64_t rows_dropped_ = 0;
  FrameRow last_row_;
};

}  // namespace hd::station
