#include "render/lens/hmd_profile_file.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <set>

#ifndef HD_SOURCE_DIR
#define HD_SOURCE_DIR ""
#endif

namespace hd::render::lens {
namespace {

namespace fs = std::filesystem;

std::string message(const std::string& file, int line, int column, const std::string& field,
                    const std::string& why) {
  std::string s = file;
  if (line > 0) {
    s += ':' + std::to_string(line);
    if (column > 0) s += ':' + std::to_string(column);
  }
  s += ": ";
  if (!field.empty()) s += field + ": ";
  return s + why;
}

// One map of the profile, with the path of keys for messages; every key must be read once.
class Fields {
 public:
  Fields(const YAML::Node& n, std::string file, std::string path)
      : node_(n), file_(std::move(file)), path_(std::move(path)) {
    if (!node_.IsMap()) fail_at(node_, path_.empty() ? "" : path_, "expected a map of keys");
  }

  [[noreturn]] void fail_at(const YAML::Node& n, const std::string& field,
                            const std::string& why) const {
    const YAML::Mark m = n.Mark();
    throw HmdProfileError(file_, m.line + 1, m.column + 1, field, why);
  }
  std::string key(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }

  bool has(const std::string& k) const { return static_cast<bool>(node_[k]); }
  YAML::Node get(const std::string& k) {
    seen_.insert(k);
    const YAML::Node n = node_[k];
    if (!n) fail_at(node_, key(k), "missing");
    return n;
  }
  double number(const std::string& k) { return as_number(get(k), key(k)); }
  double number_or(const std::string& k, double fallback) { return has(k) ? number(k) : fallback; }
  int integer(const std::string& k) {
    const YAML::Node n = get(k);
    try {
      return n.as<int>();
    } catch (const YAML::Exception&) {
      fail_at(n, key(k), "expected an integer, found '" + scalar(n) + "'");
    }
  }
  std::string text(const std::string& k) {
    const YAML::Node n = get(k);
    if (!n.IsScalar()) fail_at(n, key(k), "expected text");
    return n.Scalar();
  }
  std::vector<double> numbers(const std::string& k, std::size_t min, std::size_t max) {
    const YAML::Node n = get(k);
    if (!n.IsSequence() || n.size() < min || n.size() > max)
      fail_at(n, key(k),
              "expected a list of " +
                  (min == max ? std::to_string(min)
                              : std::to_string(min) + " to " + std::to_string(max)) +
                  " numbers");
    std::vector<double> v;
    for (std::size_t i = 0; i < n.size(); ++i)
      v.push_back(as_number(n[i], key(k) + "[" + std::to_string(i) + "]"));
    return v;
  }
  Eigen::Vector2d vec2(const std::string& k) {
    const std::vector<double> v = numbers(k, 2, 2);
    return {v[0], v[1]};
  }
  Fields map(const std::string& k) { return Fields(get(k), file_, key(k)); }
  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }

  void finish() const {
    for (const auto& kv : node_) {
      const std::string k = kv.first.Scalar();
      if (!seen_.count(k)) fail_at(kv.first, key(k), "unknown key");
    }
  }

 private:
  static std::string scalar(const YAML::Node& n) { return n.IsScalar() ? n.Scalar() : "(a list)"; }
  double as_number(const YAML::Node& n, const std::string& field) const {
    try {
      if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "");
      return n.as<double>();
    } catch (const YAML::Exception&) {
      fail_at(n, field, "expected a number, found '" + scalar(n) + "'");
    }
  }

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::set<std::string> seen_;
};

// Where a checked field sits in the file, for check_profile's problems ("lens_centre_m.left",
// "distortion.coefficients[0]", "fov_deg[1]").
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

HmdProfile read(const YAML::Node& root, const std::string& file) {
  Fields f(root, file, "");
  HmdProfile p;
  p.name = f.text("name");
  p.neutral = f.has("neutral") ? f.get("neutral").as<bool>(false) : false;
  if (f.has("source")) p.source = f.text("source");
  if (p.neutral) {
    f.finish();
    return p;
  }
  {
    Fields panel = f.map("panel");
    p.panel_width_px = panel.integer("width_px");
    p.panel_height_px = panel.integer("height_px");
    p.panel_width_m = panel.number("width_m");
    p.panel_height_m = panel.number("height_m");
    panel.finish();
  }
  if (f.has("lens_centre_m")) {
    Fields lc = f.map("lens_centre_m");
    p.lens_centre_m = {lc.vec2("left"), lc.vec2("right")};
    lc.finish();
  } else {
    // OpenHMD's description: the lens centres `lens_separation_m` apart, `lens_vertical_m` from
    // the top, symmetric about the panel's middle.
    const double sep = f.number("lens_separation_m");
    const double v = f.number("lens_vertical_m");
    p.lens_centre_m = {Eigen::Vector2d(p.panel_width_m / 2.0 - sep / 2.0, v),
                       Eigen::Vector2d(sep / 2.0, v)};
  }
  {
    Fields d = f.map("distortion");
    const YAML::Node model_node = d.get("model");
    const std::string model = model_node.IsScalar() ? model_node.Scalar() : "";
    if (model == "openhmd") {
      const std::vector<double> abcd = d.numbers("abcd", 4, 4);
      p.coefficients = {0.0, abcd[3], abcd[2], abcd[1], abcd[0]};
    } else if (model == "polynomial") {
      p.coefficients = d.numbers("coefficients", 2, 12);
    } else if (model == "mesh") {
      d.fail_at(model_node, d.key("model"),
                "mesh: distortion model 'mesh' (a distortion mesh from a file) is reserved for "
                "a future version; this version supports 'openhmd' and 'polynomial'");
    } else {
      d.fail_at(model_node, d.key("model"),
                "unknown model '" + model + "'; expected openhmd or polynomial");
    }
    const YAML::Node u = d.get("r_unit_m");
    if (u.IsSequence()) {
      p.r_unit_m = d.vec2("r_unit_m");
    } else {
      const double s = d.number("r_unit_m");
      p.r_unit_m = {s, s};
    }
    p.max_radius = d.number_or("max_radius", 0.0);
    d.finish();
  }
  if (f.has("aberration")) {
    const std::vector<double> a = f.numbers("aberration", 3, 3);
    p.aberration = {a[0], a[1], a[2]};
  }
  p.eye_to_screen_m = f.number_or("eye_to_screen_m", 0.0);
  if (f.has("fov_deg")) p.fov_deg = f.vec2("fov_deg");
  if (f.has("swap_to_photon_ms")) p.swap_to_photon_ms = f.number("swap_to_photon_ms");
  f.finish();

  if (const auto problem = check_profile(p)) {
    const YAML::Node at = locate(root, problem->field);
    const YAML::Mark m = at.Mark();
    throw HmdProfileError(file, m.line + 1, m.column + 1, problem->field,
                          problem->value + ": " + problem->why);
  }
  return p;
}

}  // namespace

HmdProfileError::HmdProfileError(const std::string& file, int line, int column, std::string field,
                                 const std::string& why)
    : std::runtime_error(message(file, line, column, field, why)),
      field_(std::move(field)),
      why_(why),
      line_(line),
      column_(column) {}

HmdProfile read_hmd_profile(const YAML::Node& node, const std::string& file) {
  return read(node, file);
}

HmdProfile load_hmd_profile(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw HmdProfileError(path, 0, 0, "", "cannot read the file");
  } catch (const YAML::ParserException& e) {
    throw HmdProfileError(path, e.mark.line + 1, e.mark.column + 1, "", e.msg);
  }
  return read(root, path);
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
      throw HmdProfileError(name_or_path, 0, 0, "", "no such profile file");
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
  throw HmdProfileError(name_or_path, 0, 0, "",
                        "no such HMD profile; shipped: " + (list.empty() ? "(none found)" : list) +
                            " (in " + shipped_profile_dir() + "), or give a .yaml path");
}

}  // namespace hd::render::lens
