#include "station/frame/station_frame.h"

#include <algorithm>
#include <cmath>

#include "core/video_age.h"
#include "core/view_measure.h"
#include "station/model/model_updater.h"

namespace hd::station {

StationFrame::StationFrame(StationFrameConfig config,
                           std::span<const drivers::CalibratedCamera> cameras,
                           drivers::PoseSource& pose, PosePredictor& predictor,
                           render::Compositor& compositor, const render::SyntheticScene* scene,
                           render::LoopClock& clock, render::LatencyRecorder& latency)
    : config_(config),
      cameras_(cameras.begin(), cameras.end()),
      pose_(pose),
      predictor_(predictor),
      compositor_(compositor),
      scene_(scene),
      clock_(clock),
      latency_(latency),
      transition_(config.transition),
      selector_(config.selection),
      m_camera_(cameras.size(), INFINITY),
      m_view_(cameras.size(), INFINITY),
      measure_(cameras.size() * 2),
      has_frame_(cameras.size(), 0),
      usable_(cameras.size(), 0),
      age_s_(cameras.size(), NAN),
      max_age_s_(cameras.size(), 0.0),
      fade_s_(cameras.size(), 0.0),
      first_new_ns_(cameras.size(), 0),
      stream_revision_(cameras.size(), 0),
      fetched_(cameras.size(), 0) {
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    const double max_age = cameras_[i].max_video_age_s > 0.0 ? cameras_[i].max_video_age_s
                                                             : core::default_max_video_age_s(0.0);
    max_age_s_[i] = max_age;
    fade_s_[i] = core::video_age_fade_s(max_age, config_.transition.time_constant_s);
  }
  out_.allocate(config_.rig.output_width(), config_.rig.output_height());
  if (config_.lens) {
    // The HUD goes where the eye sees it through the lens, not at the image's (black) corner.
    panel_.allocate(config_.lens->panel_width(), config_.lens->panel_height());
    hud_viewport_ = config_.lens->visible_rect(0);
    hud_ = render::HudStrip(hud_viewport_.width, std::max(18, hud_viewport_.height / 16), 3);
    compositor_.set_lens(config_.lens.get());
  } else {
    hud_ =
        render::HudStrip(config_.rig.eye[0].width, std::max(18, config_.rig.eye[0].height / 24), 3);
  }
  for (const drivers::CalibratedCamera& c : cameras_) {
    guidance_cameras_.push_back({c.p_c, c.T_world_real, c.d_m});
    // Not calibrated yet: no pose to guide the operator to (an invalid pose is skipped).
    if (!c.p_c.valid()) guidance_cameras_.back().T_world_real.R.setZero();
  }
  rows_.reserve(config_.max_rows);
}

void StationFrame::set_model_updater(ModelUpdater* updater) {
  model_ = updater;
}

void StationFrame::tick(const render::FrameTiming& timing) {
  // Newest frame of every camera (the device threads keep publishing meanwhile).
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    if (cameras_[i].source && cameras_[i].source->frames().fetch()) {
      if (has_frame_[i] && !usable_[i] && first_new_ns_[i] == 0)
        first_new_ns_[i] = cameras_[i].source->frames().latest().host_timestamp_ns;
      has_frame_[i] = 1;
      ++fetched_[i];
      const drivers::FrameCalibration& cal = cameras_[i].source->frames().latest().calibration;
      if (cal.present && int64_t(cal.revision) + 1 != stream_revision_[i]) {
        stream_revision_[i] = int64_t(cal.revision) + 1;
        cameras_[i].p_c = cal.p_c;
        cameras_[i].T_world_real = cal.T_world_cam;
        guidance_cameras_[i].p_c = cal.p_c;
        guidance_cameras_[i].T_world_real = cal.T_world_cam;
      }
    }
  }
  // Newest model: before its first update the mailbox shows the a-priori model (capture 0).
  const render::SyntheticScene* scene = scene_;
  int64_t model_capture_ns = 0;
  if (model_) {
    model_->models().fetch();
    const ModelSnapshot& snapshot = model_->models().latest();
    scene = &snapshot.scene;
    model_capture_ns = snapshot.capture_oldest_ns;
  }
  const int64_t texture_ns = clock_.now_ns();

  // Late latch: take every pose sample that arrived, then predict to the display time.
  history_.pull(pose_.history(), &predictor_);
  const int64_t pose_sample_ns = history_.empty() ? 0 : history_.newest().t_ns;
  const core::Pose T_world_head = config_.T_world_tracker * predictor_.predict(timing.display_ns);

  // Age of every camera's newest frame at the display time, and whether it may be shown.
  bool any_blocked = false;
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    const drivers::CameraSource* src = cameras_[c].source;
    const drivers::SourceState state = src ? src->state() : drivers::SourceState::kClosed;
    const bool streaming = state == drivers::SourceState::kStreaming;
    age_s_[c] = has_frame_[c] ? core::age_s(cameras_[c].source->frames().latest().host_timestamp_ns,
                                            timing.display_ns)
                              : NAN;
    const bool usable =
        has_frame_[c] && cameras_[c].p_c.valid() &&
        std::isfinite(core::time_extended_m(0.0, streaming, age_s_[c], max_age_s_[c]));
    any_blocked = any_blocked || (has_frame_[c] && !usable);
    if (usable != (usable_[c] != 0)) {
      usable_[c] = usable;
      if (!usability_events_.push({static_cast<int>(c), usable, timing.frame, timing.display_ns,
                                   age_s_[c], usable ? first_new_ns_[c] : 0, state}))
        ++usability_events_lost_;
      first_new_ns_[c] = 0;
    }
  }
  frames_stale_blocked_ += any_blocked;

  const render::StereoRig& rig = config_.rig;
  const int eyes = rig.eye_count();
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    double worse = 0.0;
    if (!cameras_[c].p_c.valid()) {  // no calibration yet: nothing to measure
      m_camera_[c] = INFINITY;
      continue;
    }
    for (int e = 0; e < eyes; ++e) {
      core::ViewSetup s;
      s.real = cameras_[c].p_c;
      s.T_world_real = cameras_[c].T_world_real;
      s.virt = rig.eye[static_cast<std::size_t>(e)];
      s.T_world_virt = rig.T_world_eye(T_world_head, e);
      s.d_m = cameras_[c].d_m;
      s.near_m = config_.near_m;
      s.workspace = config_.workspace;
      core::ViewMeasure& vm = measure_[c * 2 + static_cast<std::size_t>(e)];
      vm = core::measure_view(s);
      worse = render::StereoRig::worse_m(worse, vm.m);
    }
    m_view_[c] = worse;
    m_camera_[c] = usable_[c] ? worse : INFINITY;
  }
  const int chosen = selector_.update(m_camera_, timing.dt_s);
  const double m = chosen >= 0 ? m_camera_[static_cast<std::size_t>(chosen)] : INFINITY;
  // A camera left with nothing better stays on screen while its video fades out, its weight
  // held down by its frame's age.
  if (chosen >= 0) shown_ = chosen;
  const double w_cap = shown_ >= 0
                           ? core::video_weight_cap(age_s_[static_cast<std::size_t>(shown_)],
                                                    max_age_s_[static_cast<std::size_t>(shown_)],
                                                    fade_s_[static_cast<std::size_t>(shown_)])
                           : 1.0;
  const core::TransitionState ts = transition_.update(m, timing.dt_s, w_cap);
  if (chosen < 0 && ts.w_video <= 0.0) shown_ = -1;

  render::GuidanceCue cue;
  if (config_.draw_guidance && ts.w_video <= 0.0)
    cue = guidance_toward_nearest(rig.eye[0], rig.T_world_eye(T_world_head, 0), guidance_cameras_);

  // The staleness cue: the model fades with its age, video past 3/4 of its bound is framed.
  const double shown_age_s = shown_ >= 0 ? age_s_[static_cast<std::size_t>(shown_)] : NAN;
  const bool video_stale =
      shown_ >= 0 && ts.w_video > 0.0 &&
      !(shown_age_s <= (config_.marking.video_age_warn_ms > 0.0
                            ? 1e-3 * config_.marking.video_age_warn_ms
                            : 0.75 * max_age_s_[static_cast<std::size_t>(shown_)]));
  const core::MarkingParams marking =
      config_.marking.for_ages(1e3 * core::age_s(model_capture_ns, timing.display_ns), video_stale);

  const int64_t render_start_ns = clock_.now_ns();
  const drivers::Frame* video = nullptr;
  if (shown_ >= 0) video = &cameras_[static_cast<std::size_t>(shown_)].source->frames().latest();
  for (int e = 0; e < eyes; ++e) {
    render::CompositeRequest req;
    req.scene = scene;
    req.eye = rig.eye[static_cast<std::size_t>(e)];
    req.T_world_eye = rig.T_world_eye(T_world_head, e);
    req.near_m = config_.near_m;
    if (video) {
      const drivers::CalibratedCamera& cam = cameras_[static_cast<std::size_t>(shown_)];
      const core::ViewMeasure& vm =
          measure_[static_cast<std::size_t>(shown_) * 2 + static_cast<std::size_t>(e)];
      req.video = video;
      req.real = cam.p_c;
      req.T_world_real = cam.T_world_real;
      req.d_m = cam.d_m;
      req.region = vm.region;
      req.has_region = vm.has_region;
    }
    req.transition = ts;
    req.mode = config_.transition.mode;
    req.marking = marking;
    req.viewport = rig.viewport(e);
    compositor_.draw(req, out_);
    // Ghost frustum + arrow toward eye 0's nearest camera, seen from this eye; HUD on eye 0.
    render::Overlay ov;
    ov.eye = req.eye;
    ov.T_world_eye = req.T_world_eye;
    ov.near_m = req.near_m;
    ov.hud = e == 0 && !config_.lens ? &hud_ : nullptr;
    if (cue.active) {
      ov.cue = e == 0 ? cue
                      : guidance_toward_nearest(
                            req.eye, req.T_world_eye,
                            std::span(&guidance_cameras_[static_cast<std::size_t>(cue.camera)], 1));
      ov.cue.camera = cue.camera;
    }
    if (!ov.empty()) compositor_.draw_overlay(ov, req.viewport, out_);
    if (config_.lens && e == 0 && !hud_.empty()) {
      render::Overlay hud_only;
      hud_only.eye = req.eye;
      hud_only.hud = &hud_;
      compositor_.draw_overlay(hud_only, hud_viewport_, out_);
    }
  }
  if (config_.lens) compositor_.predistort(out_, panel_);
  const int64_t render_end_ns = clock_.now_ns();
  compositor_.present();
  const int64_t swap_ns = clock_.now_ns();

  render::LatencyRecord r;
  r.frame = timing.frame;
  r.pose_sample_ns = pose_sample_ns;
  if (video && ts.w_video > 0.0) {
    r.video_ns = video->host_timestamp_ns;
    r.video_is_exposure = video->device_time_trusted;
    r.video_encoded_ns = video->link.encoded_ns;
    r.video_sent_ns = video->link.sent_ns;
    r.video_received_ns = video->link.received_ns;
    r.video_decoded_ns = video->link.decoded_ns;
  }
  r.texture_update_ns = texture_ns;
  r.model_capture_ns = model_capture_ns;
  r.render_start_ns = render_start_ns;
  r.render_end_ns = render_end_ns;
  r.swap_ns = swap_ns;
  r.predicted_display_ns = timing.display_ns;
  r.missed_deadline = swap_ns > timing.deadline_ns;
  latency_.record(r);

  {
    FrameRow& row = last_row_;
    row.frame = timing.frame;
    row.m = m;
    row.w_video = ts.w_video;
    row.camera = shown_;
    row.variant = ts.variant;
    row.guidance = cue.active;
    row.guidance_distance_m = cue.distance_m;
    row.guidance_dir_x = cue.direction_px.x();
    row.guidance_dir_y = cue.direction_px.y();
    row.head_x_m = T_world_head.t.x();
    row.head_y_m = T_world_head.t.y();
    row.head_z_m = T_world_head.t.z();
    row.video_age_ms = video && ts.w_video > 0.0
                           ? 1e3 * core::age_s(video->host_timestamp_ns, timing.display_ns)
                           : NAN;
    row.model_age_ms = 1e3 * core::age_s(model_capture_ns, timing.display_ns);
  }
  if (rows_.size() < rows_.capacity())
    rows_.push_back(last_row_);
  else
    ++rows_dropped_;
}

}  // namespace hd::station
