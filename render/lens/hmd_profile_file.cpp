#include "render/lens/hmd_profile_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>

#ifndef HD_SOURCE_DIR
#define HD_SOURCE_DIR ""
#endif

namespace hd::render::lens {
namespace {

namespace fs = std::filesystem;
using config::ConfigError;
using config::YamlFields;

// Where a checked field sits under `root`, for check_profile's problems ("lens_centre_m.left",
// "distortion.coefficients[0]", "fov_deg[1]"): the deepest node of the path that exists.
YAML::Node locate(const YAML::Node& root, const std::string& field) {
  YAML::Node n = root;
  std::size_t i = 0;
  while (i < field.size()) {
    std::size_t j = field.find_first_of(".[", i);
    const std::string part = field.substr(i, j == std::string::npos ? std::string::npos : j - i);
    if (!part.empty()) {
      if (!n.IsMap() || !n[part]) return n;
      n = n[part];
    }
    if (j == std::string::npos) break;
    if (field[j] == '[') {
      const std::size_t close = field.find(']', j);
      const std::size_t idx = std::stoul(field.substr(j + 1, close - j - 1));
      if (n.IsSequence() && idx < n.size()) n = n[idx];
      i = close + 1;
      if (i < field.size() && field[i] == '.') ++i;
    } else {
      i = j + 1;
    }
  }
  return n;
}

Eigen::Vector2d vec2(const YamlFields& f, std::string_view key) {
  const std::vector<double> v = f.required_doubles(key, 2, 2);
  return {v[0], v[1]};
}

void read_distortion(const YamlFields& d, HmdProfile& p) {
  const std::string model = d.required_string("model");
  if (model == "openhmd") {
    const std::vector<double> abcd = d.required_doubles("abcd", 4, 4);
    p.coefficients = {0.0, abcd[3], abcd[2], abcd[1], abcd[0]};
  } else if (model == "polynomial") {
    p.coefficients = d.required_doubles("coefficients", 2, 12);
  } else if (model == "mesh") {
    d.fail("model",
           "mesh: distortion model 'mesh' (a distortion mesh from a file) is reserved for a "
           "future version; this version supports 'openhmd' and 'polynomial'");
  } else {
    std::string why = "unknown model '" + model + "'; expected openhmd or polynomial";
    const std::string guess = config::closest_match(model, {"openhmd", "polynomial"});
    if (!guess.empty()) why += "; did you mean '" + guess + "'?";
    d.fail("model", why);
  }
  // One radius unit for both axes, or [x, y].
  if (d.at("r_unit_m").is_list()) {
    p.r_unit_m = vec2(d, "r_unit_m");
  } else {
    const double s = d.required_double("r_unit_m");
    p.r_unit_m = {s, s};
  }
  p.max_radius = d.optional_double("max_radius", 0.0);
  d.finish();
}

HmdProfile read(const YamlFields& f) {
  HmdProfile p;
  p.name = f.required_string("name");
  p.neutral = f.optional_bool("neutral", false);
  p.source = f.optional_string("source", "");
  if (p.neutral) {
    f.finish();
    return p;
  }
  {
    const YamlFields panel = f.required_map("panel");
    p.panel_width_px = panel.required_int("width_px");
    p.panel_height_px = panel.required_int("height_px");
    p.panel_width_m = panel.required_double("width_m");
    p.panel_height_m = panel.required_double("height_m");
    panel.finish();
  }
  if (const auto lc = f.optional_map("lens_centre_m")) {
    p.lens_centre_m = {vec2(*lc, "left"), vec2(*lc, "right")};
    lc->finish();
  } else {
    // OpenHMD's description: the lens centres `lens_separation_m` apart, `lens_vertical_m` from
    // the top, symmetric about the panel's middle.
    const double sep = f.required_double("lens_separation_m");
    const double v = f.required_double("lens_vertical_m");
    p.lens_centre_m = {Eigen::Vector2d(p.panel_width_m / 2.0 - sep / 2.0, v),
                       Eigen::Vector2d(sep / 2.0, v)};
  }
  read_distortion(f.required_map("distortion"), p);
  if (f.has("aberration")) {
    const std::vector<double> a = f.required_doubles("aberration", 3, 3);
    p.aberration = {a[0], a[1], a[2]};
  }
  p.eye_to_screen_m = f.optional_double("eye_to_screen_m", 0.0);
  if (f.has("fov_deg")) p.fov_deg = vec2(f, "fov_deg");
  if (f.has("swap_to_photon_ms")) p.swap_to_photon_ms = f.required_double("swap_to_photon_ms");
  f.finish();

  // The values every key of which was well formed, checked together: reported at the field.
  if (const auto problem = check_profile(p)) {
    const YAML::Mark m = locate(f.node(), problem->field).Mark();
    throw ConfigError(f.file(), m.line >= 0 ? m.line + 1 : 0, m.column >= 0 ? m.column + 1 : 0,
                      f.field(problem->field), problem->value + ": " + problem->why);
  }
  return p;
}

}  // namespace

HmdProfile read_hmd_profile(const YamlFields& node) {
  return read(node);
}

HmdProfile read_hmd_profile(const YAML::Node& node, const std::string& file) {
  return read(YamlFields(node, file));
}

HmdProfile load_hmd_profile(const std::string& path) {
  return read(config::load_yaml_fields(path));
}

std::string shipped_profile_dir() {
  return std::string(HD_SOURCE_DIR) + "/render/lens/profiles";
}

HmdProfile find_hmd_profile(const std::string& name_or_path, const std::string& base_dir) {
  std::error_code ec;
  fs::path path = name_or_path;
  if (path.is_relative() && !base_dir.empty()) path = fs::path(base_dir) / path;
  if (name_or_path.find('/') != std::string::npos || path.extension() == ".yaml") {
    if (!fs::is_regular_file(path, ec))
      throw ConfigError(name_or_path, 0, 0, "", "no such profile file");
    return load_hmd_profile(path.string());
  }
  const fs::path shipped = fs::path(shipped_profile_dir()) / (name_or_path + ".yaml");
  if (fs::is_regular_file(shipped, ec)) return load_hmd_profile(shipped.string());
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(shipped_profile_dir(), ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  throw ConfigError(name_or_path, 0, 0, "",
                    "no such HMD profile; shipped: " + (list.empty() ? "(none found)" : list) +
                        " (in " + shipped_profile_dir() + "), or give a .yaml path");
}

}  // namespace hd::render::lens
