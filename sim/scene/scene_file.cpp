#include "sim/scene/scene_file.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "calib/calibration_file.h"
#include "core/config/video_view_field.h"
#include "core/config/yaml_fields.h"
#include "drivers/mock/trajectory.h"

namespace hd::sim {

using config::closest_match;
using config::ConfigError;
using config::Range;
using config::YamlFields;

namespace {

const std::vector<std::string> kEffectNames = {
    "sensor_noise",    "exposure",       "lens_distortion", "motion_blur",
    "rolling_shutter", "dropped_frames", "camera_delay",    "network_delay",
    "tracker_noise",   "tracker_drift",  "model_staleness"};

std::array<uint8_t, 3> read_rgb(const YamlFields& f) {
  const auto v = f.as_doubles(3, Range::closed(0, 255));
  return {static_cast<uint8_t>(std::lround(v[0])), static_cast<uint8_t>(std::lround(v[1])),
          static_cast<uint8_t>(std::lround(v[2]))};
}

void require_file(const YamlFields& f, std::string_view key, const std::string& path,
                  const char* what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    f.fail(key, std::string(what) + " '" + path + "' not found");
  }
}

SceneTexture read_texture(const YamlFields& parent) {
  SceneTexture t;
  const auto tf = parent.optional_map("texture");
  if (!tf) return t;
  t.kind = tf->optional_enum("type", {"checker", "image"}, 0) == 0 ? SceneTexture::Kind::kChecker
                                                                   : SceneTexture::Kind::kImage;
  if (t.kind == SceneTexture::Kind::kChecker) {
    if (tf->has("colors")) {
      const auto colors = tf->required_list("colors", 2);
      if (colors.size() != 2) tf->fail("colors", "expected two [r, g, b] colours");
      t.color0 = read_rgb(colors[0]);
      t.color1 = read_rgb(colors[1]);
    }
    t.cell_m = tf->optional_double("cell_m", t.cell_m, Range::positive());
  } else {
    t.image_path = tf->required_path("file");
    require_file(*tf, "file", t.image_path, "texture image");
  }
  tf->finish();
  return t;
}

/// The shape keys of a primitive (shared by static geometry and moving objects).
ScenePrimitive read_shape(const YamlFields& f, bool needs_center) {
  ScenePrimitive p;
  p.line = f.line();
  p.shape = f.required_enum("shape", {"box", "quad"}) == 0 ? ScenePrimitive::Shape::kBox
                                                           : ScenePrimitive::Shape::kQuad;
  p.center_m =
      needs_center ? f.required_vec3("center") : f.optional_vec3("center", Eigen::Vector3d::Zero());
  if (p.shape == ScenePrimitive::Shape::kBox) {
    p.size_m = f.required_vec3("size", Range::positive());
  } else {
    if (!f.has("size")) f.fail("size", "missing required key");
    const auto wh = f.at("size").as_doubles(2, Range::positive());
    p.size_m = {wh[0], wh[1], 0.0};
  }
  p.ypr_deg = f.optional_vec3("ypr_deg", Eigen::Vector3d::Zero(), Range::closed(-360, 360));
  p.texture = read_texture(f);
  return p;
}

std::vector<ObjectKeyframe> read_object_keyframes(const YamlFields& f) {
  std::vector<ObjectKeyframe> keys;
  for (const YamlFields& k : f.required_list("keyframes", 1)) {
    ObjectKeyframe kf;
    kf.t_s = k.required_double("t", Range::non_negative());
    kf.position_m = k.required_vec3("position");
    kf.yaw_deg = k.optional_double("yaw_deg", 0.0, Range::closed(-3600, 3600));
    k.finish();
    if (!keys.empty() && !(kf.t_s > keys.back().t_s)) {
      k.fail("t", "keyframe times must increase");
    }
    keys.push_back(kf);
  }
  return keys;
}

core::Pose read_camera_pose(const YamlFields& pf) {
  core::Pose pose;
  pose.t = pf.required_vec3("position");
  if (pf.has("look_at")) {
    if (pf.has("ypr_deg")) pf.fail("look_at", "give either look_at or ypr_deg, not both");
    const Eigen::Vector3d target = pf.required_vec3("look_at");
    const Eigen::Vector3d down = Eigen::Vector3d::UnitY();  // world "down" (y down)
    const Eigen::Vector3d z = target - pose.t;
    if (z.norm() < 1e-9) pf.fail("look_at", "the target is the camera's own position");
    const Eigen::Vector3d zn = z.normalized();
    const Eigen::Vector3d x = down.cross(zn);
    if (x.norm() < 1e-6) pf.fail("look_at", "looking straight up or down: the roll is undefined");
    pose.R.col(0) = x.normalized();
    pose.R.col(2) = zn;
    pose.R.col(1) = zn.cross(pose.R.col(0));
  } else {
    pose.R = rotation_from_ypr_deg(
        pf.optional_vec3("ypr_deg", Eigen::Vector3d::Zero(), Range::closed(-360, 360)));
  }
  pf.finish();
  return pose;
}

SceneCamera read_camera(const YamlFields& c) {
  SceneCamera cam;
  cam.name = c.required_string("name");
  cam.id = "sim:" + cam.name;
  cam.line = c.line();
  if (cam.name.empty()) c.fail("name", "a camera needs a name");
  cam.rate_hz = c.optional_double("rate_hz", 30.0, Range{0.0, 1000.0, true, false});
  cam.d_m = c.required_double("d_m", Range::positive());
  cam.video_view = config::read_video_view(c);
  cam.max_video_age_ms =
      c.optional_double("max_video_age_ms", 0.0, Range{0.0, 60'000.0, true, false});
  bool have_pose = false;
  if (c.has("calibration")) {
    if (c.has("intrinsics")) c.fail("intrinsics", "give either calibration or intrinsics");
    cam.calibration_file = c.required_path("calibration");
    require_file(c, "calibration", cam.calibration_file, "calibration file");
    try {
      const calib::CalibrationFile cf = calib::read_calibration_file(cam.calibration_file);
      cam.p_c = cf.pinhole;
      if (cf.camera_pose) {
        cam.T_world_cam = *cf.camera_pose;
        have_pose = true;
      }
    } catch (const std::exception& e) {
      c.fail("calibration", e.what());
    }
  } else {
    const YamlFields k = c.required_map("intrinsics");
    core::Pinhole& p = cam.p_c;
    p.fx = k.required_double("fx", Range::positive());
    p.fy = k.required_double("fy", Range::positive());
    p.width = k.required_int("width", Range::closed(1, 16384));
    p.height = k.required_int("height", Range::closed(1, 16384));
    p.cx = k.optional_double("cx", p.width / 2.0);
    p.cy = k.optional_double("cy", p.height / 2.0);
    k.finish();
    if (const auto d = c.optional_map("distortion")) {
      const char* names[5] = {"k1", "k2", "p1", "p2", "k3"};
      for (int i = 0; i < 5; ++i) {
        p.distortion[static_cast<std::size_t>(i)] =
            d->optional_double(names[i], 0.0, Range::closed(-10, 10));
      }
      p.distortion_count = 5;
      d->finish();
    }
  }
  if (c.has("pose")) {
    if (have_pose) c.fail("pose", "the calibration file already gives this camera's pose");
    cam.T_world_cam = read_camera_pose(c.required_map("pose"));
    have_pose = true;
  }
  if (!have_pose) c.fail("pose", "missing required key (the camera's pose)");
  c.finish();
  return cam;
}

SceneHead read_head(const YamlFields& h) {
  SceneHead head;
  head.rate_hz = h.optional_double("rate_hz", head.rate_hz, Range{0.0, 100000.0, true, false});
  if (h.has("trajectory")) {
    if (h.has("keyframes")) h.fail("keyframes", "give either trajectory or keyframes");
    head.trajectory_csv = h.required_path("trajectory");
    require_file(h, "trajectory", head.trajectory_csv, "trajectory file");
    try {
      (void)drivers::Trajectory::load_csv(head.trajectory_csv);
    } catch (const std::exception& e) {
      h.fail("trajectory", e.what());
    }
  } else {
    for (const YamlFields& k : h.required_list("keyframes", 1)) {
      HeadKeyframe kf;
      kf.t_s = k.required_double("t", Range::non_negative());
      kf.position_m = k.required_vec3("position");
      kf.ypr_deg = k.optional_vec3("ypr_deg", Eigen::Vector3d::Zero(), Range::closed(-360, 360));
      k.finish();
      if (!head.keyframes.empty() && !(kf.t_s > head.keyframes.back().t_s)) {
        k.fail("t", "keyframe times must increase");
      }
      head.keyframes.push_back(kf);
    }
    head.smooth = h.optional_bool("smooth", head.smooth);
  }
  h.finish();
  return head;
}

uint64_t read_seed(const YamlFields& p, uint64_t fallback) {
  return static_cast<uint64_t>(
      p.optional_int("seed", static_cast<int>(fallback), Range::closed(0, 2147483647)));
}

DelayEffect read_delay(const YamlFields& p) {
  DelayEffect d;
  d.mean_ms = p.required_double("mean_ms", Range::closed(0, 10000));
  d.jitter_ms = p.optional_double("jitter_ms", 0.0, Range::closed(0, 1000));
  d.seed = read_seed(p, d.seed);
  return d;
}

Eigen::Vector3d read_unit(const YamlFields& p, std::string_view key, const Eigen::Vector3d& def) {
  const Eigen::Vector3d v = p.optional_vec3(key, def);
  if (v.norm() < 1e-9) p.fail(key, "must not be the zero vector");
  return v.normalized();
}

void read_effect(const YamlFields& item, SceneEffects& fx) {
  // An item is either a bare name ("- lens_distortion") or a one-key mapping to its parameters.
  std::string name;
  if (item.is_scalar()) {
    name = item.as_string();
  } else if (item.node().IsMap() && item.node().size() == 1 &&
             item.node().begin()->first.IsScalar()) {
    name = item.node().begin()->first.Scalar();
  } else {
    item.fail("expected an effect name, or one effect name mapped to its parameters");
  }
  // A bare name has no parameters: an empty mapping (its errors carry the item's line).
  const YamlFields params =
      item.is_scalar() ? YamlFields(YAML::Node(YAML::NodeType::Null), item.file(), item.path())
                       : item.at(name);
  if (!params.is_map()) params.fail("expected the effect's parameters as a mapping");
  const auto index = std::find(kEffectNames.begin(), kEffectNames.end(), name);
  if (index == kEffectNames.end()) {
    std::string why = "unknown effect '" + name + "'";
    const std::string guess = closest_match(name, kEffectNames);
    why += guess.empty() ? " (known: sensor_noise, exposure, lens_distortion, motion_blur, "
                           "rolling_shutter, dropped_frames, camera_delay, network_delay, "
                           "tracker_noise, tracker_drift, model_staleness)"
                         : "; did you mean '" + guess + "'?";
    item.fail(why);
  }
  const YamlFields& p = params;
  auto once = [&](auto& slot) {
    if (slot) item.fail("effect '" + name + "' listed twice");
  };
  if (name == "sensor_noise") {
    once(fx.sensor_noise);
    SensorNoiseEffect e;
    e.sigma_dn = p.required_double("sigma_dn", Range::closed(0, 128));
    e.seed = read_seed(p, e.seed);
    fx.sensor_noise = e;
  } else if (name == "exposure") {
    once(fx.exposure);
    ExposureEffect e;
    e.gain = p.optional_double("gain", 1.0, Range{0.0, 100.0, true, false});
    e.offset_dn = p.optional_double("offset_dn", 0.0, Range::closed(-255, 255));
    fx.exposure = e;
  } else if (name == "lens_distortion") {
    once(fx.lens_distortion);
    fx.lens_distortion = LensDistortionEffect{};
  } else if (name == "motion_blur") {
    once(fx.motion_blur);
    MotionBlurEffect e;
    e.exposure_ms = p.required_double("exposure_ms", Range{0.0, 1000.0, true, false});
    e.samples = p.optional_int("samples", e.samples, Range::closed(2, 64));
    fx.motion_blur = e;
  } else if (name == "rolling_shutter") {
    once(fx.rolling_shutter);
    RollingShutterEffect e;
    e.readout_ms = p.required_double("readout_ms", Range{0.0, 1000.0, true, false});
    e.bands = p.optional_int("bands", e.bands, Range::closed(2, 1024));
    fx.rolling_shutter = e;
  } else if (name == "dropped_frames") {
    once(fx.dropped_frames);
    DroppedFramesEffect e;
    e.probability = p.required_double("probability", Range::half_open(0, 1));
    e.seed = read_seed(p, e.seed);
    fx.dropped_frames = e;
  } else if (name == "camera_delay") {
    once(fx.camera_delay);
    fx.camera_delay = read_delay(p);
  } else if (name == "network_delay") {
    once(fx.network_delay);
    fx.network_delay = read_delay(p);
  } else if (name == "tracker_noise") {
    once(fx.tracker_noise);
    TrackerNoiseEffect e;
    e.position_sigma_m =
        p.optional_double("position_sigma_m", e.position_sigma_m, Range::closed(0, 1));
    e.orientation_sigma_deg =
        p.optional_double("orientation_sigma_deg", e.orientation_sigma_deg, Range::closed(0, 45));
    e.seed = read_seed(p, e.seed);
    fx.tracker_noise = e;
  } else if (name == "tracker_drift") {
    once(fx.tracker_drift);
    TrackerDriftEffect e;
    e.position_m_s = p.optional_double("position_m_s", e.position_m_s, Range::closed(0, 1));
    e.orientation_deg_s =
        p.optional_double("orientation_deg_s", e.orientation_deg_s, Range::closed(0, 90));
    e.direction = read_unit(p, "direction", e.direction);
    e.axis = read_unit(p, "axis", e.axis);
    fx.tracker_drift = e;
  } else if (name == "model_staleness") {
    once(fx.model_staleness);
    ModelStalenessEffect e;
    e.period_s = p.required_double("period_s", Range{0.0, 3600.0, true, false});
    e.delay_s = p.optional_double("delay_s", e.delay_s, Range::closed(0, 3600));
    fx.model_staleness = e;
  }
  p.finish();
}

Scene read_scene(const YamlFields& root) {
  Scene s;
  s.file = root.file();
  s.name = root.optional_string("name", std::filesystem::path(root.file()).stem().string());
  s.duration_s = root.optional_double("duration_s", s.duration_s, Range{0.0, 86400.0, true, false});
  s.loop = root.optional_bool("loop", s.loop);
  if (root.has("background")) s.background_rgb = read_rgb(root.at("background"));

  const YamlFields ws = root.required_map("workspace");
  s.workspace.min_m = ws.required_vec3("min");
  s.workspace.max_m = ws.required_vec3("max");
  if (!s.workspace.valid()) ws.fail("max", "every coordinate of max must be >= min");
  ws.finish();

  for (const YamlFields& g : root.optional_list("geometry")) {
    ScenePrimitive p = read_shape(g, true);
    p.name = g.optional_string("name", "");
    g.finish();
    s.geometry.push_back(std::move(p));
  }

  const auto objects = root.optional_list("objects");
  for (const YamlFields& o : objects) {
    SceneObject obj;
    obj.name = o.required_string("name");
    for (const SceneObject& other : s.objects) {
      if (other.name == obj.name) o.fail("name", "object '" + obj.name + "' defined twice");
    }
    obj.shape = read_shape(o, false);
    obj.shape.name = obj.name;
    obj.keyframes = read_object_keyframes(o);
    if (const auto c = o.optional_map("carried_by")) {
      obj.carrier = c->required_string("object");
      obj.pick_s = c->required_double("pick_s", Range::non_negative());
      obj.place_s = c->required_double("place_s", Range::non_negative());
      if (!(obj.place_s > obj.pick_s)) c->fail("place_s", "must be after pick_s");
      c->finish();
    }
    o.finish();
    s.objects.push_back(std::move(obj));
  }
  // Carriers are checked once all objects are known, so the order in the file does not matter.
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const SceneObject& o = s.objects[i];
    if (o.carrier.empty()) continue;
    const YamlFields c = objects[i].at("carried_by");
    const auto it = std::find_if(s.objects.begin(), s.objects.end(),
                                 [&](const SceneObject& x) { return x.name == o.carrier; });
    if (it == s.objects.end() || it->name == o.name) {
      c.fail("object", "no other object named '" + o.carrier + "'");
    }
    if (!it->carrier.empty()) c.fail("object", "'" + o.carrier + "' is itself carried");
  }

  for (const YamlFields& c : root.required_list("cameras", 1)) {
    SceneCamera cam = read_camera(c);
    for (const SceneCamera& other : s.cameras) {
      if (other.name == cam.name) c.fail("name", "camera '" + cam.name + "' defined twice");
    }
    s.cameras.push_back(std::move(cam));
  }

  s.head = read_head(root.required_map("head"));

  for (const YamlFields& e : root.optional_list("effects")) {
    try {
      read_effect(e, s.effects);
    } catch (const ConfigError& err) {
      // A bare name ("- motion_blur") has no node of its own for a missing parameter: report
      // the list item's line.
      if (err.line() > 0) throw;
      throw ConfigError(err.file(), e.line(), e.column(), err.field(), err.why());
    }
  }

  std::vector<std::string> camera_names;
  for (const SceneCamera& c : s.cameras) camera_names.push_back(c.name);
  for (const YamlFields& sp : root.optional_list("stereo"))
    s.stereo.push_back(read_stereo_pair(sp, camera_names));

  if (const auto m = root.optional_map("model")) {
    const std::size_t k = m->optional_enum("moved_objects", {"reconstructed", "ground-truth"}, 0);
    s.model.moved_objects = k == 0 ? MovedObjects::kReconstructed : MovedObjects::kGroundTruth;
    m->finish();
  }

  if (const auto st = root.optional_map("station")) {
    if (st->has("m_t")) s.station.m_t = st->required_double("m_t", Range::non_negative());
    if (st->has("eps")) s.station.eps = st->required_double("eps", Range::non_negative());
    if (st->has("eye_width")) {
      s.station.eye_width = st->required_int("eye_width", Range::closed(16, 4096));
    }
    if (st->has("eye_height")) {
      s.station.eye_height = st->required_int("eye_height", Range::closed(16, 4096));
    }
    st->finish();
  }
  root.finish();
  return s;
}

}  // namespace

SceneStereoPair read_stereo_pair(const YamlFields& sp,
                                 const std::vector<std::string>& camera_names) {
  SceneStereoPair pair;
  pair.line = sp.line();
  for (const char* key : {"left", "right"}) {
    const std::string name = sp.required_string(key);
    const bool known =
        std::find(camera_names.begin(), camera_names.end(), name) != camera_names.end();
    if (!known) sp.fail(key, "no camera named '" + name + "'");
    (std::string_view(key) == "left" ? pair.left : pair.right) = name;
  }
  if (pair.left == pair.right) sp.fail("right", "a pair needs two different cameras");
  pair.min_disparity_px =
      sp.optional_int("min_disparity_px", pair.min_disparity_px, Range::closed(1, 1024));
  pair.num_disparities_px =
      sp.optional_int("num_disparities_px", pair.num_disparities_px, Range::closed(16, 1024));
  const std::vector<std::string> matchers{"sgbm-scaled", "sgbm", "bm"};
  pair.matcher = matchers[sp.optional_enum("matcher", matchers, 0)];
  pair.every_updates = sp.optional_int("every_updates", pair.every_updates, Range::closed(1, 1000));
  sp.finish();
  return pair;
}

Scene parse_scene(const std::string& text, const std::string& name) {
  return read_scene(YamlFields(config::parse_yaml(text, name), name));
}

Scene load_scene(const std::string& path) {
  return read_scene(config::load_yaml_fields(path));
}

}  // namespace hd::sim
