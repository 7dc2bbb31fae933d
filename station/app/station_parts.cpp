#include "station/app/station_parts.h"

#include <cstdio>

#include "recon/matcher_config.h"
#include "render/lens/hmd_profile_file.h"
#include "render/loop/stepped_clock.h"
#include "station/app/report_text.h"

namespace hd::station {

StationParts::~StationParts() {
  stop();
}

void StationParts::start() {
  if (started_) return;
  started_ = true;
  if (stepped) {
    for (auto& c : stepped->cameras) c->start();
    stepped->head->start();
    return;
  }
  for (StationCamera& c : cameras) c.pipeline->start();
  if (head) head->start();
  if (updater) updater->start();
}

void StationParts::stop() {
  if (!started_) return;
  started_ = false;
  if (stepped) {
    stepped->head->stop();
    for (auto& c : stepped->cameras) c->stop();
    return;
  }
  if (updater) updater->stop();
  if (head) head->stop();
  for (StationCamera& c : cameras) c.pipeline->stop();
}

std::vector<drivers::CalibratedCamera> StationParts::calibrated_cameras() const {
  std::vector<drivers::CalibratedCamera> out;
  for (const StationCamera& c : cameras) out.push_back(c.calibrated);
  return out;
}

std::vector<std::string> StationParts::camera_names() const {
  std::vector<std::string> out;
  for (const StationCamera& c : cameras) out.push_back(c.name);
  return out;
}

int StationParts::camera_index(const std::string& name) const {
  for (std::size_t i = 0; i < cameras.size(); ++i)
    if (cameras[i].description.name == name) return static_cast<int>(i);
  return -1;
}

std::string add_model_updater(StationParts& p, station::ModelUpdaterConfig uc,
                              const std::vector<sim::SceneStereoPair>& stereo,
                              const core::WorkspaceBox& workspace) {
  std::vector<station::ModelCamera> mc;
  for (const StationCamera& c : p.cameras)
    mc.push_back({&c.pipeline->model_frames(), c.calibrated.p_c, c.calibrated.T_world_real});
  for (const sim::SceneStereoPair& sp : stereo) {
    const int l = p.camera_index(sp.left), r = p.camera_index(sp.right);
    if (l < 0 || r < 0) {
      p.report.missing("stereo pair", sp.left + "+" + sp.right, "a camera of the pair did not open",
                       true);
      continue;
    }
    uc.stereo_pairs.push_back(
        model_stereo_pair(sp, static_cast<std::size_t>(l), static_cast<std::size_t>(r), workspace));
  }
  // Stepped: the run moves the updater's clock to each moment it drives it at.
  if (p.stepped)
    p.updater_clock = std::make_unique<render::SteppedLoopClock>();
  else
    p.updater_clock = std::make_unique<render::MonotonicLoopClock>();
  try {
    p.updater = std::make_unique<station::ModelUpdater>(p.model, mc, uc, *p.updater_clock);
  } catch (const std::exception& e) {
    // A pair that cannot be one (RigError names why): re-textured without reconstruction.
    p.report.missing("stereo pair", "model", e.what(), true);
    uc.stereo_pairs.clear();
    p.updater = std::make_unique<station::ModelUpdater>(p.model, mc, uc, *p.updater_clock);
  }
  std::string names;
  for (const station::ModelStereoPair& mp : p.updater->config().stereo_pairs)
    names += (names.empty() ? "" : ", ") + mp.name;
  return names;
}

station::ModelStereoPair model_stereo_pair(const sim::SceneStereoPair& sp, std::size_t left,
                                           std::size_t right, const core::WorkspaceBox& workspace) {
  station::ModelStereoPair mp;
  mp.name = sp.left + "+" + sp.right;
  mp.left = left;
  mp.right = right;
  mp.every_updates = sp.every_updates;
  mp.reconstruction.matcher.kind = recon::matcher_kind_from_string(sp.matcher);
  mp.reconstruction.matcher.min_disparity_px = sp.min_disparity_px;
  mp.reconstruction.matcher.num_disparities_px = sp.num_disparities_px;
  mp.reconstruction.measure_row_error = false;  // a diagnostic for hybrid-recon, not per update
  mp.bounds = workspace;
  mp.use_bounds = true;
  return mp;
}

void configure_frame(StationParts& p, DisplayConfig display, core::TransitionParams transition,
                     core::MarkingParams marking, const core::WorkspaceBox& workspace,
                     const std::string& predictor, const RunOptions& o) {
  if (!o.hmd.empty()) {
    try {
      display.hmd = render::lens::find_hmd_profile(o.hmd, "");
    } catch (const config::ConfigError& e) {
      throw config::ConfigError("--hmd", 0, 0, "", e.what());
    }
  }
  if (o.mono && !display.hmd.neutral) {
    p.report.note("hmd", "profile " + display.hmd.name + " not used: --mono (one eye)");
    display.hmd = render::lens::HmdProfile::make_neutral();
  }
  if (o.mono) display.stereo = false;
  std::shared_ptr<const render::lens::LensWarp> lens;
  if (!display.hmd.neutral) {
    // The lens decides the eyes: the size and field of view it needs (p_o, so E, W, C and m
    // are computed for the view the operator sees), and the panel's own latency.
    display.stereo = true;
    lens = std::make_shared<render::lens::LensWarp>(display.hmd);
    display.eye = lens->eye(0);
    if (display.hmd.swap_to_photon_ms && o.scanout_ms < 0.0)
      display.scanout_ms = *display.hmd.swap_to_photon_ms;
    if (o.eye_width > 0 || o.eye_height > 0)
      p.report.note("hmd", "--eye-width/--eye-height ignored: the lens sets the eye size");
  }
  if (!lens && (o.eye_width > 0 || o.eye_height > 0)) {
    const int w = o.eye_width > 0 ? o.eye_width : display.eye.width;
    const int h = o.eye_height > 0 ? o.eye_height : display.eye.height;
    // Keep the field of view: scale the focal lengths with the width.
    const double s = static_cast<double>(w) / display.eye.width;
    display.eye = core::Pinhole::centred(display.eye.fx * s, w, h);
  }
  if (o.rate_hz > 0.0) display.rate_hz = o.rate_hz;
  if (o.scanout_ms >= 0.0) display.scanout_ms = o.scanout_ms;
  if (o.m_t >= 0.0) transition.m_t = o.m_t;
  if (o.eps >= 0.0) transition.eps = o.eps;
  if (!o.transition_mode.empty())
    for (std::size_t i = 0; i < transition_mode_names().size(); ++i)
      if (transition_mode_names()[i] == o.transition_mode)
        transition.mode = static_cast<core::TransitionMode>(i);
  if (!o.marking.empty())
    for (std::size_t i = 0; i < marking_style_names().size(); ++i)
      if (marking_style_names()[i] == o.marking) marking.style = static_cast<core::MarkingStyle>(i);

  station::StationFrameConfig& c = p.frame_config;
  c.rig = display.stereo ? render::StereoRig{} : render::StereoRig::monitor(display.eye);
  if (display.stereo) {
    c.rig.eye = {display.eye, display.eye};
    c.rig.ipd_m = display.ipd_m;
  }
  if (lens) c.rig.eye = {lens->eye(0), lens->eye(1)};  // mirrored lenses: own principal points
  c.lens = lens;
  c.workspace = workspace;
  c.transition = transition;
  c.marking = marking;
  // The head arrives already in the workspace frame (AlignedPoseSource).
  c.T_world_tracker = core::Pose::identity();
  // The run logs frames itself (FrameLog, touched up front); StationFrame keeps none.
  c.max_rows = 0;
  p.rate_hz = display.rate_hz;
  p.scanout_ms = display.scanout_ms;
  p.predictor = o.predictor.empty() ? predictor : o.predictor;
  p.monitor = display.monitor;

  p.report.note("eyes",
                display.stereo
                    ? fmt("stereo, %gx%g px per eye, IPD %g mm", display.eye.width,
                          display.eye.height, display.ipd_m * 1e3)
                    : fmt("monitor (one eye), %gx%g px", display.eye.width, display.eye.height));
  p.report.note("eye intrinsics", fmt("fx %.1f fy %.1f", display.eye.fx, display.eye.fy) +
                                      fmt(" cx %.1f cy %.1f", display.eye.cx, display.eye.cy));
  if (lens) {
    const render::lens::HmdProfile& h = display.hmd;
    p.report.note("hmd", h.name + " (" + h.source + ")");
    p.report.note("hmd panel",
                  fmt("%gx%g px, ", h.panel_width_px, h.panel_height_px) +
                      fmt("%.4gx%.4g m, swap-to-photon ", h.panel_width_m, h.panel_height_m) +
                      (h.swap_to_photon_ms ? fmt("%g ms (profile)", *h.swap_to_photon_ms)
                                           : std::string("not in the profile")));
    p.report.note("hmd eye image",
                  fmt("%gx%g px per eye, field of view %.1f", lens->eye_width(), lens->eye_height(),
                      lens->eye_fov_x_deg()) +
                      fmt(" x %.1f deg, pre-distorted R/G/B scale %.4f / 1 / %.4f",
                          lens->eye_fov_y_deg(), lens->channel_scale(0), lens->channel_scale(2)));
  } else {
    p.report.note("hmd", "none (neutral: no lens, nothing pre-distorted)");
  }
  p.report.note("transition", std::string(transition_mode_name(transition.mode)) +
                                  fmt(", m_t %g px, eps %g px", transition.m_t, transition.eps) +
                                  fmt(", hysteresis %g px, time constant %g s",
                                      transition.hysteresis, transition.time_constant_s));
  p.report.note("marking", marking_style_name(marking.style));
  p.report.note("workspace", fmt("min (%g, %g, %g) m", workspace.min_m.x(), workspace.min_m.y(),
                                 workspace.min_m.z()) +
                                 fmt(" max (%g, %g, %g) m", workspace.max_m.x(),
                                     workspace.max_m.y(), workspace.max_m.z()));
  p.report.note(
      "loop",
      fmt("%g Hz, scan-out %g ms, predictor ", display.rate_hz, display.scanout_ms) + p.predictor);
}

}  // namespace hd::station
