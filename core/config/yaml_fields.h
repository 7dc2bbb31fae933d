#pragma once
// A small checked reader over yaml-cpp nodes, shared by every YAML file the programs read (scene
// files, station.yaml, remote.yaml, HMD profiles): every value is read through it so a mistake is
// reported as "<file>:<line>:<col>: <field>: <why>" (ConfigError) instead of a yaml-cpp exception
// without context or, worse, a silent default. It lives in core/config (its own library,
// hd_config, so hd_core itself stays Eigen-only) because render/ reads HMD profiles and sits below
// sim/, where the reader first was.
//
//   YamlFields root = load_yaml_fields("scenes/default.yaml");
//   double d_m = root.required_map("camera").required_double("d_m", Range::positive());
//   root.finish();  // any key not read above is rejected ("did you mean ...")
//
// Keys are remembered as they are asked for (has/required/optional/allow), so finish() knows the
// valid set without a second list that could drift from the code that reads it.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/config/config_error.h"

namespace hd::config {

/// Bounds for a numeric field; each end open or closed.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;
  bool hi_open = false;

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity()}; }
  static Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity()}; }
  static Range closed(double lo, double hi) { return {lo, hi}; }
  /// [lo, hi)
  static Range half_open(double lo, double hi) { return {lo, hi, false, true}; }

  bool contains(double v) const;
  std::string describe() const;  ///< e.g. "> 0", "in [0, 1]"
};

/// Reads and parses a YAML file. An unreadable file or a syntax error is a ConfigError naming the
/// file (and for a syntax error its line and column).
YAML::Node load_yaml_file(const std::string& path);
/// Parses YAML text; `name` stands for the file in error messages.
YAML::Node parse_yaml(const std::string& text, const std::string& name);

/// The candidate closest to `word` (case-insensitive edit distance; a candidate that is `word`
/// plus a "_suffix" counts as one edit) if close enough to be a likely typo, else "".
std::string closest_match(std::string_view word, const std::vector<std::string>& candidates);

/// One node of a parsed document with where it came from (file, dotted field path).
class YamlFields {
 public:
  YamlFields(YAML::Node node, std::string file, std::string path = "");
  YamlFields(const YamlFields&) = default;
  YamlFields(YamlFields&&) = default;
  // yaml-cpp's Node::operator= writes into the node it refers to (changing the parsed document),
  // so a YamlFields is never reassigned.
  YamlFields& operator=(const YamlFields&) = delete;
  YamlFields& operator=(YamlFields&&) = delete;

  const YAML::Node& node() const { return node_; }
  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  int line() const;    ///< 1-based, 0 if unknown
  int column() const;  ///< 1-based, 0 if unknown
  /// The dotted path of `key` under this node ("cameras[1].intrinsics" + "fx").
  std::string field(std::string_view key) const;
  /// The directory of the file, for paths given relative to it ("" = current directory).
  std::string base_directory() const;

  // ---- this node as a mapping (a null node counts as an empty mapping) ----
  bool has(std::string_view key) const;    ///< present and not null; remembers the key as valid
  void allow(std::string_view key) const;  ///< a valid key this code does not read

  double required_double(std::string_view key, Range range = Range::any()) const;
  double optional_double(std::string_view key, double fallback, Range range = Range::any()) const;
  int required_int(std::string_view key, Range range = Range::any()) const;
  int optional_int(std::string_view key, int fallback, Range range = Range::any()) const;
  bool required_bool(std::string_view key) const;
  bool optional_bool(std::string_view key, bool fallback) const;
  std::string required_string(std::string_view key) const;
  std::string optional_string(std::string_view key, std::string fallback) const;
  /// A string naming a file, resolved against the directory of this file (absolute paths kept).
  /// Existence is the caller's check (fail(key, ...) reports it at the right line).
  std::string required_path(std::string_view key) const;
  std::optional<std::string> optional_path(std::string_view key) const;
  Eigen::Vector3d required_vec3(std::string_view key, Range each = Range::any()) const;
  Eigen::Vector3d optional_vec3(std::string_view key, const Eigen::Vector3d& fallback,
                                Range each = Range::any()) const;
  /// A list of `min_count` to `max_count` numbers (as_doubles).
  std::vector<double> required_doubles(std::string_view key, std::size_t min_count,
                                       std::size_t max_count, Range each = Range::any()) const;
  /// Index into `names` of the value (a string); anything else lists the choices.
  std::size_t required_enum(std::string_view key, const std::vector<std::string>& names) const;
  std::size_t optional_enum(std::string_view key, const std::vector<std::string>& names,
                            std::size_t fallback) const;

  YamlFields required_map(std::string_view key) const;
  std::optional<YamlFields> optional_map(std::string_view key) const;
  /// The items of a sequence (each with path "key[i]"); `min_items` checked.
  std::vector<YamlFields> required_list(std::string_view key, std::size_t min_items = 0) const;
  std::vector<YamlFields> optional_list(std::string_view key) const;  ///< absent: empty
  /// The value of `key` without checks (for a caller that dispatches on its type).
  YamlFields at(std::string_view key) const;

  /// Rejects any key of this mapping that was not asked for, and keys given twice.
  void finish() const;

  // ---- this node as a value (list items, or a value obtained through at()) ----
  double as_double(Range range = Range::any()) const;
  int as_int(Range range = Range::any()) const;
  bool as_bool() const;
  std::string as_string() const;
  Eigen::Vector3d as_vec3(Range each = Range::any()) const;
  std::vector<double> as_doubles(std::size_t count, Range each = Range::any()) const;
  /// A list of `min_count` to `max_count` numbers (each item's field is "path[i]").
  std::vector<double> as_doubles(std::size_t min_count, std::size_t max_count,
                                 Range each = Range::any()) const;
  std::size_t as_enum(const std::vector<std::string>& names) const;
  bool is_map() const { return node_.IsMap() || node_.IsNull(); }
  bool is_list() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  /// A ConfigError at this node / at `key` (its value if present, else this mapping).
  ConfigError error(const std::string& why) const;
  ConfigError error(std::string_view key, const std::string& why) const;
  [[noreturn]] void fail(const std::string& why) const { throw error(why); }
  [[noreturn]] void fail(std::string_view key, const std::string& why) const {
    throw error(key, why);
  }

 private:
  YAML::Node lookup(std::string_view key) const;  ///< const access: never inserts
  YamlFields child(std::string_view key) const;   ///< present (checked by the caller)
  YamlFields required(std::string_view key) const;
  void expect_map() const;
  std::string kind() const;  ///< "a mapping", "a list", "a scalar", "nothing"

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::shared_ptr<std::vector<std::string>> known_;  ///< keys asked for (shared by copies)
};

/// load_yaml_file() wrapped as the root YamlFields of `path`.
YamlFields load_yaml_fields(const std::string& path);

}  // namespace hd::config
