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
      pose_(pose),
      predictor_(predictor),
      compositor_(compositor),
      scene_(scene),
      clock_(clock),
      latency_(latency),
      transition_(config.transition),
      selector_(config.selection) {
  m_camera_.assign(cameras.size(), INFINITY);
  m_view_.assign(cameras.size(), INFINITY);
  for (const drivers::CalibratedCamera& c : cameras) {
    CameraState& s = cameras_.emplace_back();
    s.calibrated = c;
    s.max_age_s = c.max_video_age_s > 0.0 ? c.max_video_age_s : core::default_max_video_age_s(0.0);
    s.fade_s = core::video_age_fade_s(s.max_age_s, config_.transition.time_constant_s);
    s.d_m = c.d_m;
    if (c.video_view == core::VideoView::kFittedPlane)
      s.fitted = std::make_unique<FittedPlane>(c.p_c, c.d_m);
    guidance_cameras_.push_back({c.p_c, c.T_world_real, c.d_m});
    // Not calibrated yet: no pose to guide the operator to (an invalid pose is skipped).
    if (!c.p_c.valid()) guidance_cameras_.back().T_world_real.R.setZero();
  }
  out_.allocate(config_.rig.output_width(), config_.rig.output_height());
  if (config_.lens) {
    // The HUD goes where the eye sees it through the lens, not at the image's (black) corner.
    panel_.allocate(config_.lens->panel_width(), config_.lens->panel_height());
    hud_viewport_ = config_.lens->visible_rect(0);
    hud_ = render::HudStrip(hud_viewport_.width, std::max(18, hud_viewport_.height / 16), 5,
                            kHudGraphLines);
    compositor_.set_lens(config_.lens.get());
  } else {
    hud_ = render::HudStrip(config_.rig.eye[0].width, std::max(18, config_.rig.eye[0].height / 24),
                            5, kHudGraphLines);
  }
  rows_.reserve(config_.max_rows);
}

std::vector<uint64_t> StationFrame::frames_fetched() const {
  std::vector<uint64_t> out;
  for (const CameraState& c : cameras_) out.push_back(c.fetched);
  return out;
}

void StationFrame::set_model_updater(ModelUpdater* updater) {
  model_ = updater;
}

void StationFrame::tick(const render::FrameTiming& timing) {
  // Newest frame of every camera (the device threads keep publishing meanwhile).
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    CameraState& c = cameras_[i];
    drivers::CameraSource* src = c.calibrated.source;
    if (src == nullptr || !src->frames().fetch()) continue;
    if (c.has_frame && !c.usable && c.first_new_ns == 0)
      c.first_new_ns = src->frames().latest().host_timestamp_ns;
    c.has_frame = true;
    ++c.fetched;
    const drivers::FrameCalibration& cal = src->frames().latest().calibration;
    if (cal.present && int64_t(cal.revision) + 1 != c.stream_revision) {
      c.stream_revision = int64_t(cal.revision) + 1;
      c.calibrated.p_c = cal.p_c;
      c.calibrated.T_world_real = cal.T_world_cam;
      if (c.fitted) c.fitted->set_camera(cal.p_c);  // allocates only if the size grew
      guidance_cameras_[i].p_c = cal.p_c;
      guidance_cameras_[i].T_world_real = cal.T_world_cam;
    }
  }
  // Newest model: before its first update the mailbox shows the a-priori model (capture 0).
  const render::SyntheticScene* scene = scene_;
  int64_t model_capture_ns = 0, model_reconstructed_ns = 0, model_published_ns = 0;
  if (model_) {
    model_->models().fetch();
    const ModelSnapshot& snapshot = model_->models().latest();
    scene = &snapshot.scene;
    model_capture_ns = snapshot.capture_oldest_ns;
    if (snapshot.update != 0) {
      model_reconstructed_ns = snapshot.reconstructed_ns;
      model_published_ns = snapshot.published_ns;
    }
  }
  const int64_t texture_ns = clock_.now_ns();

  // Late latch: take every pose sample that arrived, then predict to the display time.
  history_.pull(pose_.history(), &predictor_);
  const int64_t pose_sample_ns = history_.empty() ? 0 : history_.newest().t_ns;
  const core::Pose T_world_head = config_.T_world_tracker * predictor_.predict(timing.display_ns);

  // Age of every camera's newest frame at the display time, and whether it may be shown.
  bool any_blocked = false;
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    CameraState& c = cameras_[i];
    drivers::CameraSource* src = c.calibrated.source;
    const drivers::SourceState state = src ? src->state() : drivers::SourceState::kClosed;
    const bool streaming = state == drivers::SourceState::kStreaming;
    c.age_s = c.has_frame ? core::age_s(src->frames().latest().host_timestamp_ns, timing.display_ns)
                          : NAN;
    const bool usable = c.has_frame && c.calibrated.p_c.valid() &&
                        std::isfinite(core::time_extended_m(0.0, streaming, c.age_s, c.max_age_s));
    any_blocked = any_blocked || (c.has_frame && !usable);
    if (usable != c.usable) {
      c.usable = usable;
      if (!usability_events_.push({static_cast<int>(i), usable, timing.frame, timing.display_ns,
                                   c.age_s, usable ? c.first_new_ns : 0, state}))
        ++usability_events_lost_;
      c.first_new_ns = 0;
    }
  }
  frames_stale_blocked_ += any_blocked;

  const render::StereoRig& rig = config_.rig;
  const int eyes = rig.eye_count();
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    CameraState& c = cameras_[i];
    double worse = 0.0;
    if (!c.calibrated.p_c.valid()) {  // no calibration yet: nothing to measure
      m_camera_[i] = INFINITY;
      continue;
    }
    if (c.fitted) {
      // The eyes' part of the frame last frame (the whole frame when they saw none of it).
      core::PixelRect seen{INFINITY, INFINITY, -INFINITY, -INFINITY};
      for (int e = 0; e < eyes; ++e) {
        const core::ViewMeasure& vm = c.measure[static_cast<std::size_t>(e)];
        if (!vm.has_region) continue;
        seen = {std::min(seen.u_min, vm.region.u_min), std::min(seen.v_min, vm.region.v_min),
                std::max(seen.u_max, vm.region.u_max), std::max(seen.v_max, vm.region.v_max)};
      }
      c.d_m = c.fitted->update(scene, c.calibrated.T_world_real,
                               seen.u_min <= seen.u_max ? &seen : nullptr, timing.dt_s);
    }
    for (int e = 0; e < eyes; ++e) {
      core::ViewSetup s;
      s.real = c.calibrated.p_c;
      s.T_world_real = c.calibrated.T_world_real;
      s.virt = rig.eye[static_cast<std::size_t>(e)];
      s.T_world_virt = rig.T_world_eye(T_world_head, e);
      s.d_m = c.d_m;
      s.near_m = config_.near_m;
      s.workspace = config_.workspace;
      core::ViewMeasure& vm = c.measure[static_cast<std::size_t>(e)];
      vm = core::measure_view(s);
      worse = render::StereoRig::worse_m(worse, vm.m);
    }
    m_view_[i] = worse;
    m_camera_[i] = c.usable ? worse : INFINITY;
  }
  const int chosen = selector_.update(m_camera_, timing.dt_s);
  const double m = chosen >= 0 ? m_camera_[static_cast<std::size_t>(chosen)] : INFINITY;
  // A camera left with nothing better stays on screen while its video fades out, its weight
  // held down by its frame's age.
  if (chosen >= 0) shown_ = chosen;
  const CameraState* shown = shown_ >= 0 ? &cameras_[static_cast<std::size_t>(shown_)] : nullptr;
  const double w_cap =
      shown ? core::video_weight_cap(shown->age_s, shown->max_age_s, shown->fade_s) : 1.0;
  const core::TransitionState ts = transition_.update(m, timing.dt_s, w_cap);
  if (chosen < 0 && ts.w_video <= 0.0) {
    shown_ = -1;
    shown = nullptr;
  }

  render::GuidanceCue cue;
  if (config_.draw_guidance && ts.w_video <= 0.0)
    cue = guidance_toward_nearest(rig.eye[0], rig.T_world_eye(T_world_head, 0), guidance_cameras_);

  // The staleness cue: the model fades with its age, video past 3/4 of its bound is framed.
  const bool video_stale = shown && ts.w_video > 0.0 &&
                           !(shown->age_s <= (config_.marking.video_age_warn_ms > 0.0
                                                  ? 1e-3 * config_.marking.video_age_warn_ms
                                                  : 0.75 * shown->max_age_s));
  const core::MarkingParams marking =
      config_.marking.for_ages(1e3 * core::age_s(model_capture_ns, timing.display_ns), video_stale);

  const int64_t render_start_ns = clock_.now_ns();
  const drivers::Frame* video = nullptr;
  if (shown) video = &shown->calibrated.source->frames().latest();
  for (int e = 0; e < eyes; ++e) {
    render::CompositeRequest req;
    req.scene = scene;
    req.eye = rig.eye[static_cast<std::size_t>(e)];
    req.T_world_eye = rig.T_world_eye(T_world_head, e);
    req.near_m = config_.near_m;
    if (video) {
      const drivers::CalibratedCamera& cam = shown->calibrated;
      const core::ViewMeasure& vm = shown->measure[static_cast<std::size_t>(e)];
      req.video = video;
      req.real = cam.p_c;
      req.T_world_real = cam.T_world_real;
      req.d_m = shown->d_m;
      req.video_view = cam.video_view;
      req.region = vm.region;
      req.has_region = vm.has_region;
    }
    req.transition = ts;
    req.mode = config_.transition.mode;
    req.marking = marking;
    req.viewport = rig.viewport(e);
    compositor_.draw(req, out_);
    last_requests_[static_cast<std::size_t>(e)] = req;
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
  r.model_reconstructed_ns = model_reconstructed_ns;
  r.model_published_ns = model_published_ns;
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
    row.w_cap = w_cap;
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
