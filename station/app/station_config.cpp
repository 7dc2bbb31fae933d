#include "station/app/station_config.h"

#include <filesystem>

#include <yaml-cpp/yaml.h>

#include "calib/calibration_file.h"
#include "core/config/video_view_field.h"
#include "core/config/yaml_fields.h"
#include "render/lens/hmd_profile_file.h"
#include "sim/scene/scene.h"
#include "sim/scene/scene_file.h"

namespace hd::station {
namespace {

using config::Range;
using config::YamlFields;

// `{position_m: [x, y, z], ypr_deg: [yaw, pitch, roll]}`, the scene files' convention.
core::Pose read_pose(const config::YamlFields& f) {
  core::Pose p;
  p.t = f.optional_vec3("position_m", Eigen::Vector3d::Zero());
  p.R = sim::rotation_from_ypr_deg(
      f.optional_vec3("ypr_deg", Eigen::Vector3d::Zero(), Range::closed(-360.0, 360.0)));
  f.finish();
  return p;
}

CameraConfig read_camera(const config::YamlFields& f, std::size_t index) {
  CameraConfig c;
  c.line = f.line();
  c.name = f.optional_string("name", "camera" + std::to_string(index));
  c.id = f.required_string("id");
  if (c.id.empty())
    f.fail("id", "empty; expected /dev/videoN, a GigE id, rtp://HOST:PORT or mock[:WxH]");
  const bool network = c.id.rfind("rtp://", 0) == 0;
  // A network camera whose sender streams its calibration needs no file (docs/network.md).
  if (network) {
    if (auto p = f.optional_path("calibration")) c.calibration_file = *p;
  } else {
    c.calibration_file = f.required_path("calibration");
  }
  c.d_m = f.required_double("d_m", Range::positive());
  c.video_view = config::read_video_view(f);
  c.max_video_age_ms =
      f.optional_double("max_video_age_ms", 0.0, Range{0.0, 60'000.0, true, false});
  c.optional = f.optional_bool("optional", false);
  if (auto k = f.optional_path("key_file")) {
    if (!network) f.fail("key_file", "only a network camera (id rtp://HOST:PORT) takes a key file");
    c.key_file = *k;
  }
  const std::string clock = f.optional_string("clock", "measured");
  if (clock != "measured" && clock != "synchronized")
    f.fail("clock", "'" + clock + "'; expected measured or synchronized");
  if (clock == "synchronized" && !network)
    f.fail("clock", "only a network camera (id rtp://HOST:PORT) has a sender clock");
  c.clock_synchronized = clock == "synchronized";
  c.clock_error_ms = f.optional_double("clock_error_ms", 1.0, Range::closed(0.0, 10'000.0));
  std::optional<core::Pose> pose_override;
  if (auto p = f.optional_map("pose")) pose_override = read_pose(*p);
  f.finish();
  if (c.calibration_file.empty()) {
    if (pose_override)
      f.fail("pose", "needs a calibration: file (a streamed calibration carries its own P_c)");
    c.p_c = core::Pinhole{};  // not valid: from the stream, once it arrives
    c.p_c.width = c.p_c.height = 0;
    c.T_world_cam.R.setZero();  // no pose until then
    return c;
  }

  calib::CalibrationFile cal;
  try {
    cal = calib::read_calibration_file(c.calibration_file);
  } catch (const calib::CalibrationFileError& e) {
    f.fail("calibration", e.what());
  }
  c.p_c = cal.pinhole;
  if (pose_override)
    c.T_world_cam = *pose_override;
  else if (cal.camera_pose)
    c.T_world_cam = *cal.camera_pose;
  else
    f.fail("calibration", c.calibration_file +
                              " has no camera pose (run `hybrid-calib pose`) and no pose: is "
                              "given here");
  return c;
}

TrackerConfig read_tracker(const config::YamlFields& f) {
  TrackerConfig t;
  t.line = f.line();
  t.id = f.required_string("id");
  if (t.id.empty()) f.fail("id", "empty; expected mock, hid, /dev/hidrawN or VID:PID");
  t.optional = f.optional_bool("optional", false);
  f.finish();
  return t;
}

DisplayConfig read_display(const config::YamlFields& f) {
  DisplayConfig d;
  d.monitor = f.optional_int("monitor", -1, Range::closed(-1, 16));
  d.fullscreen = f.optional_bool("fullscreen", false);
  if (d.fullscreen && d.monitor < 0) d.monitor = 0;
  d.stereo = f.optional_bool("stereo", true);
  d.ipd_m = f.optional_double("ipd_m", 0.064, Range::half_open(0.0, 0.2));
  if (d.stereo && d.ipd_m <= 0.0) f.fail("ipd_m", "must be > 0 for a stereo display");
  d.rate_hz = f.optional_double("rate_hz", 90.0, Range::closed(1.0, 1000.0));
  d.scanout_ms = f.optional_double("scanout_ms", 2.0, Range::closed(0.0, 100.0));
  int w = 480, h = 400;
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  if (auto e = f.optional_map("eye")) {
    w = e->optional_int("width", w, Range::closed(16, 8192));
    h = e->optional_int("height", h, Range::closed(16, 8192));
    fx = e->optional_double("fx", 0.9 * w, Range::positive());
    fy = e->optional_double("fy", fx, Range::positive());
    cx = e->optional_double("cx", w / 2.0, Range::closed(0.0, w));
    cy = e->optional_double("cy", h / 2.0, Range::closed(0.0, h));
    e->finish();
  } else {
    fx = fy = 0.9 * w;
    cx = w / 2.0;
    cy = h / 2.0;
  }
  d.eye = core::Pinhole::centred(fx, w, h);
  d.eye.fy = fy;
  d.eye.cx = cx;
  d.eye.cy = cy;
  if (f.node()["hmd"]) {
    // A name or file (resolved against this file's directory), or the profile inline.
    const config::YamlFields h = f.at("hmd");
    try {
      if (h.is_scalar()) {
        const std::string base = std::filesystem::path(f.file()).parent_path().string();
        d.hmd = render::lens::find_hmd_profile(h.as_string(), base);
      } else {
        d.hmd = render::lens::read_hmd_profile(h.node(), f.file());
      }
    } catch (const config::ConfigError& e) {
      if (h.is_scalar()) f.fail("hmd", e.what());
      throw config::ConfigError(f.file(), e.line(), e.column(), "display.hmd." + e.field(),
                                e.why());
    }
    if (!d.hmd.neutral && !d.stereo)
      f.fail("hmd", "the HMD profile '" + d.hmd.name + "' needs stereo: true (two eyes)");
  }
  f.finish();
  return d;
}

core::TransitionParams read_transition(const config::YamlFields& f) {
  core::TransitionParams t;
  t.mode = static_cast<core::TransitionMode>(
      f.optional_enum("mode", transition_mode_names(), static_cast<std::size_t>(t.mode)));
  t.m_t = f.optional_double("m_t", t.m_t, Range::positive());
  t.eps = f.optional_double("eps", t.eps, Range::non_negative());
  t.hysteresis = f.optional_double("hysteresis", t.hysteresis, Range::non_negative());
  t.time_constant_s =
      f.optional_double("time_constant_s", t.time_constant_s, Range::closed(0.0, 10.0));
  f.finish();
  return t;
}

core::MarkingParams read_marking(const config::YamlFields& f) {
  core::MarkingParams m;
  m.style = static_cast<core::MarkingStyle>(
      f.optional_enum("style", marking_style_names(), static_cast<std::size_t>(m.style)));
  m.frame_width_px = f.optional_int("frame_width_px", m.frame_width_px, Range::closed(1, 256));
  m.synthetic_desaturation = f.optional_double("synthetic_desaturation", m.synthetic_desaturation,
                                               Range::closed(0.0, 1.0));
  m.checker_cell_px = f.optional_int("checker_cell_px", m.checker_cell_px, Range::closed(1, 1024));
  m.checker_contrast =
      f.optional_double("checker_contrast", m.checker_contrast, Range::closed(0.0, 1.0));
  m.model_age_fresh_ms =
      f.optional_double("model_age_fresh_ms", m.model_age_fresh_ms, Range::non_negative());
  m.model_age_full_ms =
      f.optional_double("model_age_full_ms", m.model_age_full_ms, Range::non_negative());
  if (m.model_age_full_ms < m.model_age_fresh_ms)
    f.fail("model_age_full_ms", "must be >= model_age_fresh_ms");
  m.stale_fade_max = f.optional_double("stale_fade", m.stale_fade_max, Range::closed(0.0, 1.0));
  m.stale_checker_contrast = f.optional_double("stale_checker_contrast", m.stale_checker_contrast,
                                               Range::closed(0.0, 1.0));
  m.video_age_warn_ms =
      f.optional_double("video_age_warn_ms", m.video_age_warn_ms, Range::non_negative());
  f.finish();
  return m;
}

core::WorkspaceBox read_workspace(const config::YamlFields& f) {
  core::WorkspaceBox w;
  w.min_m = f.required_vec3("min_m");
  w.max_m = f.required_vec3("max_m");
  if (!w.valid()) f.fail("max_m", "must be >= min_m on every axis");
  f.finish();
  return w;
}

StationConfig read_station(const config::YamlFields& root) {
  StationConfig s;
  s.file = root.file();
  const std::vector<config::YamlFields> cams = root.required_list("cameras", 1);
  for (std::size_t i = 0; i < cams.size(); ++i) s.cameras.push_back(read_camera(cams[i], i));
  s.tracker = read_tracker(root.required_map("tracker"));
  if (auto d = root.optional_map("display")) s.display = read_display(*d);
  if (auto t = root.optional_map("transition")) s.transition = read_transition(*t);
  if (auto m = root.optional_map("marking")) s.marking = read_marking(*m);
  s.workspace = read_workspace(root.required_map("workspace"));
  if (auto t = root.optional_map("tracker_to_workspace")) s.T_world_tracker = read_pose(*t);
  if (auto h = root.optional_map("home_pose")) s.T_world_home = read_pose(*h);
  if (auto m = root.optional_map("model")) {
    if (auto p = m->optional_path("scene")) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(*p, ec)) m->fail("scene", "no such file: " + *p);
      s.model.scene_file = *p;
    }
    s.model.refresh_period_s =
        m->optional_double("refresh_period_s", s.model.refresh_period_s, Range::positive());
    std::vector<std::string> names;
    for (const CameraConfig& c : s.cameras) names.push_back(c.name);
    for (const config::YamlFields& sp : m->optional_list("stereo")) {
      s.model.stereo.push_back(sim::read_stereo_pair(sp, names));
      // A pair's rig is fixed at start, from files.
      for (const std::string& n : {s.model.stereo.back().left, s.model.stereo.back().right})
        for (const CameraConfig& c : s.cameras)
          if (c.name == n && c.calibration_file.empty())
            sp.fail("left", "camera '" + n +
                                "' has no calibration: file; a stereo pair needs both cameras' "
                                "files");
    }
    m->finish();
  }
  static const std::vector<std::string> predictors{"none", "cv", "kalman"};
  s.predictor = predictors[root.optional_enum("predictor", predictors, 2)];
  root.finish();
  return s;
}

}  // namespace

const std::vector<std::string>& transition_mode_names() {
  // Order = core::TransitionMode.
  static const std::vector<std::string> names{"abrupt", "global_blend", "per_pixel"};
  return names;
}

const std::vector<std::string>& marking_style_names() {
  // Order = core::MarkingStyle.
  static const std::vector<std::string> names{"none", "frame", "desaturate", "checker"};
  return names;
}

const char* transition_mode_name(core::TransitionMode mode) {
  return transition_mode_names()[static_cast<std::size_t>(mode)].c_str();
}

const char* marking_style_name(core::MarkingStyle style) {
  return marking_style_names()[static_cast<std::size_t>(style)].c_str();
}

StationConfig load_station_config(const std::string& path) {
  return read_station(config::load_yaml_fields(path));
}

StationConfig parse_station_config(const std::string& text, const std::string& name) {
  return read_station(config::YamlFields(config::parse_yaml(text, name), name));
}

}  // namespace hd::station
