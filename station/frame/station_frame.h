#pragma once
// One frame of the station, as the frame loop runs it: late-latched predicted pose, m for every
// camera and eye, camera choice, transition, compositing, guidance, latency record.

#include <array>
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
#include "drivers/source_state.h"
#include "drivers/spsc_ring.h"
#include "render/compositor/compositor.h"
#include "render/latency/latency_recorder.h"
#include "render/lens/lens_warp.h"
#include "render/loop/frame_loop.h"
#include "render/overlay/guidance_cue.h"
#include "render/overlay/hud_strip.h"
#include "render/stereo/stereo_rig.h"
#include "station/prediction/pose_history.h"
#include "station/selection/camera_selector.h"
#include "station/video/fitted_plane.h"

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
  /// The cap the video's age put on w_video this frame (core::video_weight_cap; 1: none), kept
  /// so `hybrid-station score` can replay the transition with other m_t and eps.
  double w_cap = 1.0;
  int camera = -1;
  core::Variant variant = core::Variant::kSynthetic;
  bool guidance = false;
  double guidance_distance_m = 0.0;
  double guidance_dir_x = 0.0, guidance_dir_y = 0.0;
  double head_x_m = 0.0, head_y_m = 0.0, head_z_m = 0.0;  ///< predicted head position
  /// Age at the predicted display time of the video drawn (NaN: no video on screen) and of the
  /// model's textures (NaN: the a-priori model, whose capture time is unknown), milliseconds.
  double video_age_ms = 0.0;
  double model_age_ms = 0.0;
};

/// A camera became usable (its source streams and its newest frame is younger than its
/// max_video_age_s at the display time) or stopped being usable, seen in frame `frame`.
struct CameraUsabilityEvent {
  int camera = -1;
  bool usable = false;
  uint64_t frame = 0;
  int64_t display_ns = 0;    ///< the predicted display time of that frame (CLOCK_MONOTONIC)
  double video_age_s = 0.0;  ///< the newest frame's age then (NaN: no frame yet)
  /// Becoming usable again: the host timestamp of the first frame the camera delivered after it
  /// became unusable (0: none, or the first time it is usable), so how long its return took to
  /// reach the screen can be read off frame timestamps.
  int64_t first_new_frame_ns = 0;
  drivers::SourceState state = drivers::SourceState::kClosed;
};

/// Calibration: a camera's p_c / P_c are its CalibratedCamera's until a frame brings its own
/// (Frame::calibration: a network camera whose sender streams them), from then on the newest
/// frame's, taken when its revision changes (a fixed-size copy: no allocation, no lock). A camera
/// whose p_c is not valid (an rtp:// camera without a calibration file, before its first
/// calibration arrived) is never usable and never a guidance target.
///
/// Per-frame work. Everything is sized in the constructor; tick() does not allocate (shown by
/// loop_no_allocation_test), lock or throw, and calls nothing of a camera but frames() (a
/// lock-free mailbox) and state() (an atomic), so a device that hangs cannot hold a frame up.
///
/// Each camera's video view (drivers::CalibratedCamera::video_view) decides the plane it is
/// measured and drawn on: its d_m, or for fitted-plane a d fitted to the model inside the part of
/// the frame the eyes saw in the previous frame; model-depth is drawn on the model's surfaces
/// (the compositor's) and measured, as the paper does, on its plane at d_m.
///
/// Time is an input of the decision (docs/truth.md): a camera is usable only while its source
/// is streaming and its newest frame is younger than its max_video_age_s at the predicted
/// display time; otherwise its m is +inf (core::time_extended_m) and the selector leaves it.
/// The camera on screen leaves through the transition (a blend fades out, an abrupt switch
/// switches) with its weight capped by its frame's age (core::video_weight_cap), so no frame
/// older than 1.5 max_video_age_s is ever drawn.
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
  /// The same with a graph below the text (the stage delays, on a key; empty: none), as tall as
  /// kHudGraphLines lines of the HUD.
  void set_hud(std::string_view text, const render::HudGraph& graph) { hud_.set_text(text, graph); }
  static constexpr int kHudGraphLines = 5;
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
  /// Frames in which each camera showed a new frame (index = camera). Not for the tick's thread
  /// while it runs: it allocates.
  std::vector<uint64_t> frames_fetched() const;
  /// The oldest usability change not taken yet (call between ticks, on the render thread).
  bool pop_usability_event(CameraUsabilityEvent& out) { return usability_events_.pop(out); }
  /// Usability changes lost because nobody took them (the ring holds 256).
  uint64_t usability_events_lost() const { return usability_events_lost_; }
  /// Frames in which at least one camera that had delivered a frame was not usable (its video
  /// withheld because it was too old or its source not streaming).
  uint64_t frames_stale_blocked() const { return frames_stale_blocked_; }
  /// Whether camera i was usable in the newest frame.
  bool usable(std::size_t i) const { return cameras_[i].usable; }
  /// The p_c / P_c camera i is measured and drawn with now: its CalibratedCamera's, or the
  /// calibration its newest frame brought (a network camera whose sender streams it).
  const drivers::CalibratedCamera& camera(std::size_t i) const { return cameras_[i].calibrated; }
  /// The newest frame's geometric m per camera (worse eye) at the predicted pose, whether or
  /// not its video is usable: what bandwidth-follows-the-view decides on (CameraNeedPolicy).
  std::span<const double> view_m() const { return m_view_; }
  /// What eye `eye` was drawn from in the newest frame (pose, model, the camera on screen or
  /// fading out with its frame, transition): valid until the next tick. `hybrid-station score`
  /// draws the same frame as pure video and pure model from it.
  const render::CompositeRequest& last_request(int eye) const {
    return last_requests_[static_cast<std::size_t>(eye)];
  }

 private:
  /// What the tick knows of one camera between frames.
  struct CameraState {
    drivers::CalibratedCamera calibrated;      ///< p_c / P_c as measured and drawn now
    std::array<core::ViewMeasure, 2> measure;  ///< per eye
    bool has_frame = false;
    bool usable = false;
    double age_s = NAN;        ///< newest frame's age at the display time
    double max_age_s = 0.0;    ///< its bound (core/video_age.h)
    double fade_s = 0.0;       ///< core::video_age_fade_s
    int64_t first_new_ns = 0;  ///< first frame fetched while unusable
    /// The stream calibration in use (revision + 1; 0: the CalibratedCamera's own).
    int64_t stream_revision = 0;
    uint64_t fetched = 0;  ///< frames in which it showed a new frame
    /// The plane its video is measured and drawn on this frame: calibrated.d_m, or with the
    /// fitted-plane view the fitted d (station/video/fitted_plane.h).
    double d_m = 1.0;
    std::unique_ptr<FittedPlane> fitted;  ///< the fitted-plane view only
  };

  StationFrameConfig config_;
  std::vector<CameraState> cameras_;
  /// The selector's, the need policy's and the guidance's inputs, one entry per camera: kept
  /// contiguous for them, written from cameras_ each tick.
  std::vector<double> m_camera_;  ///< worse-eye m per camera (+inf: not usable)
  std::vector<double> m_view_;    ///< worse-eye m per camera, usable or not
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
  int shown_ = -1;                   ///< the camera whose video is drawn (chosen, or fading out)
  drivers::SpscRing<CameraUsabilityEvent, 256> usability_events_;
  uint64_t usability_events_lost_ = 0;
  uint64_t frames_stale_blocked_ = 0;
  std::vector<FrameRow> rows_;
  uint64_t rows_dropped_ = 0;
  FrameRow last_row_;
  std::array<render::CompositeRequest, 2> last_requests_{};
};

}  // namespace hd::station
