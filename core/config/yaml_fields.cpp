#include "core/config/yaml_fields.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hd::config {

namespace {

std::string number_text(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0u : 1u)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

int one_based(int zero_based) {
  return zero_based >= 0 ? zero_based + 1 : 0;
}

}  // namespace

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  const bool lo_ok = lo_open ? v > lo : v >= lo;
  const bool hi_ok = hi_open ? v < hi : v <= hi;
  return lo_ok && hi_ok;
}

std::string Range::describe() const {
  const bool has_lo = !std::isinf(lo);
  const bool has_hi = !std::isinf(hi);
  if (has_lo && has_hi) {
    return std::string("in ") + (lo_open ? "(" : "[") + number_text(lo) + ", " + number_text(hi) +
           (hi_open ? ")" : "]");
  }
  if (has_lo) return (lo_open ? "> " : ">= ") + number_text(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + number_text(hi);
  return "finite";
}

YAML::Node parse_yaml(const std::string& text, const std::string& name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(name, one_based(e.mark.line), one_based(e.mark.column), "",
                      "YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name, one_based(e.mark.line), one_based(e.mark.column), "",
                      "YAML error: " + e.msg);
  }
}

YAML::Node load_yaml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, 0, 0, "", std::string("cannot read: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ConfigError(path, 0, 0, "", "read error");
  return parse_yaml(text.str(), path);
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  const std::string w = lower(word);
  // A typo is a few edits; allow more for long words, but never so many that short unrelated
  // words match.
  const std::size_t limit = w.size() <= 3 ? 1 : (w.size() <= 6 ? 2 : 3);
  std::string best;
  std::size_t best_d = limit + 1;
  for (const auto& c : candidates) {
    const std::string lc = lower(c);
    std::size_t d = edit_distance(w, lc);
    // A key without its unit suffix ("rate" for "rate_hz") is a likely slip too.
    if (!w.empty() && lc.size() > w.size() && lc.compare(0, w.size(), w) == 0 &&
        lc[w.size()] == '_') {
      d = std::min<std::size_t>(d, 1);
    }
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best;
}

YamlFields::YamlFields(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)),
      file_(std::move(file)),
      path_(std::move(path)),
      known_(std::make_shared<std::vector<std::string>>()) {}

int YamlFields::line() const {
  return one_based(node_.Mark().line);
}
int YamlFields::column() const {
  return one_based(node_.Mark().column);
}

std::string YamlFields::field(std::string_view key) const {
  if (path_.empty()) return std::string(key);
  return path_ + "." + std::string(key);
}

std::string YamlFields::base_directory() const {
  return std::filesystem::path(file_).parent_path().string();
}

ConfigError YamlFields::error(const std::string& why) const {
  return ConfigError(file_, line(), column(), path_, why);
}

ConfigError YamlFields::error(std::string_view key, const std::string& why) const {
  const YAML::Node value = lookup(key);
  if (value && value.Mark().line >= 0) {
    return ConfigError(file_, one_based(value.Mark().line), one_based(value.Mark().column),
                       field(key), why);
  }
  return ConfigError(file_, line(), column(), field(key), why);
}

std::string YamlFields::kind() const {
  if (!node_ || node_.IsNull()) return "nothing";
  if (node_.IsMap()) return "a mapping";
  if (node_.IsSequence()) return "a list";
  return "'" + node_.Scalar() + "'";
}

void YamlFields::expect_map() const {
  if (!is_map()) fail("expected a mapping of keys, got " + kind());
}

YAML::Node YamlFields::lookup(std::string_view key) const {
  if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  const YAML::Node& n = node_;  // const operator[] never inserts
  return n[std::string(key)];
}

void YamlFields::allow(std::string_view key) const {
  if (std::find(known_->begin(), known_->end(), key) == known_->end()) {
    known_->emplace_back(key);
  }
}

bool YamlFields::has(std::string_view key) const {
  expect_map();
  allow(key);
  const YAML::Node v = lookup(key);
  return v.IsDefined() && !v.IsNull();
}

YamlFields YamlFields::child(std::string_view key) const {
  return YamlFields(lookup(key), file_, field(key));
}

YamlFields YamlFields::at(std::string_view key) const {
  allow(key);
  return child(key);
}

YamlFields YamlFields::required(std::string_view key) const {
  if (!has(key)) {
    const YAML::Node v = lookup(key);
    fail(key, v.IsDefined() ? "a value is required" : "missing required key");
  }
  return child(key);
}

double YamlFields::as_double(Range range) const {
  double v = 0;
  if (!node_.IsScalar() || !YAML::convert<double>::decode(node_, v) || !std::isfinite(v)) {
    fail("expected a number, got " + kind());
  }
  if (!range.contains(v))
    fail("value " + number_text(v) + " out of range: must be " + range.describe());
  return v;
}

int YamlFields::as_int(Range range) const {
  long long v = 0;
  if (!node_.IsScalar() || !YAML::convert<long long>::decode(node_, v)) {
    fail("expected an integer, got " + kind());
  }
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max() ||
      !range.contains(static_cast<double>(v))) {
    fail("value " + std::to_string(v) + " out of range: must be " + range.describe());
  }
  return static_cast<int>(v);
}

bool YamlFields::as_bool() const {
  bool v = false;
  if (!node_.IsScalar() || !YAML::convert<bool>::decode(node_, v)) {
    fail("expected true or false, got " + kind());
  }
  return v;
}

std::string YamlFields::as_string() const {
  if (!node_.IsScalar()) fail("expected a string, got " + kind());
  return node_.Scalar();
}

std::vector<double> YamlFields::as_doubles(std::size_t count, Range each) const {
  return as_doubles(count, count, each);
}

std::vector<double> YamlFields::as_doubles(std::size_t min_count, std::size_t max_count,
                                           Range each) const {
  if (!node_.IsSequence() || node_.size() < min_count || node_.size() > max_count) {
    const std::string count = min_count == max_count
                                  ? std::to_string(min_count)
                                  : std::to_string(min_count) + " to " + std::to_string(max_count);
    fail("expected a list of " + count + " numbers, got " +
         (node_.IsSequence() ? "a list of " + std::to_string(node_.size()) : kind()));
  }
  std::vector<double> out;
  out.reserve(node_.size());
  for (std::size_t i = 0; i < node_.size(); ++i) {
    out.push_back(
        YamlFields(node_[i], file_, path_ + "[" + std::to_string(i) + "]").as_double(each));
  }
  return out;
}

Eigen::Vector3d YamlFields::as_vec3(Range each) const {
  const auto v = as_doubles(3, each);
  return {v[0], v[1], v[2]};
}

std::size_t YamlFields::as_enum(const std::vector<std::string>& names) const {
  if (!node_.IsScalar()) fail("expected one of: " + join(names) + "; got " + kind());
  const std::string& s = node_.Scalar();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == s) return i;
  }
  std::string why = "unknown value '" + s + "' (expected one of: " + join(names) + ")";
  const std::string guess = closest_match(s, names);
  if (!guess.empty()) why += "; did you mean '" + guess + "'?";
  fail(why);
}

double YamlFields::required_double(std::string_view key, Range range) const {
  return required(key).as_double(range);
}
double YamlFields::optional_double(std::string_view key, double fallback, Range range) const {
  return has(key) ? child(key).as_double(range) : fallback;
}
int YamlFields::required_int(std::string_view key, Range range) const {
  return required(key).as_int(range);
}
int YamlFields::optional_int(std::string_view key, int fallback, Range range) const {
  return has(key) ? child(key).as_int(range) : fallback;
}
bool YamlFields::required_bool(std::string_view key) const {
  return required(key).as_bool();
}
bool YamlFields::optional_bool(std::string_view key, bool fallback) const {
  return has(key) ? child(key).as_bool() : fallback;
}
std::string YamlFields::required_string(std::string_view key) const {
  return required(key).as_string();
}
std::string YamlFields::optional_string(std::string_view key, std::string fallback) const {
  return has(key) ? child(key).as_string() : fallback;
}

std::string YamlFields::required_path(std::string_view key) const {
  const std::string value = required_string(key);
  if (value.empty()) fail(key, "a file name is required");
  const std::filesystem::path p(value);
  if (p.is_absolute()) return value;
  return (std::filesystem::path(base_directory()) / p).lexically_normal().string();
}

std::optional<std::string> YamlFields::optional_path(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return required_path(key);
}

Eigen::Vector3d YamlFields::required_vec3(std::string_view key, Range each) const {
  return required(key).as_vec3(each);
}
Eigen::Vector3d YamlFields::optional_vec3(std::string_view key, const Eigen::Vector3d& fallback,
                                          Range each) const {
  return has(key) ? child(key).as_vec3(each) : fallback;
}

std::vector<double> YamlFields::required_doubles(std::string_view key, std::size_t min_count,
                                                 std::size_t max_count, Range each) const {
  return required(key).as_doubles(min_count, max_count, each);
}

std::size_t YamlFields::required_enum(std::string_view key,
                                      const std::vector<std::string>& names) const {
  return required(key).as_enum(names);
}
std::size_t YamlFields::optional_enum(std::string_view key, const std::vector<std::string>& names,
                                      std::size_t fallback) const {
  return has(key) ? child(key).as_enum(names) : fallback;
}

YamlFields YamlFields::required_map(std::string_view key) const {
  YamlFields c = required(key);
  c.expect_map();
  return c;
}

std::optional<YamlFields> YamlFields::optional_map(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  YamlFields c = child(key);
  c.expect_map();
  return c;
}

std::vector<YamlFields> YamlFields::required_list(std::string_view key,
                                                  std::size_t min_items) const {
  const YamlFields c = required(key);
  if (!c.is_list()) c.fail("expected a list, got " + c.kind());
  if (c.node_.size() < min_items) {
    c.fail("expected at least " + std::to_string(min_items) + " item(s), got " +
           std::to_string(c.node_.size()));
  }
  std::vector<YamlFields> items;
  items.reserve(c.node_.size());
  for (std::size_t i = 0; i < c.node_.size(); ++i) {
    items.emplace_back(c.node_[i], file_, c.path_ + "[" + std::to_string(i) + "]");
  }
  return items;
}

std::vector<YamlFields> YamlFields::optional_list(std::string_view key) const {
  if (!has(key)) return {};
  return required_list(key);
}

void YamlFields::finish() const {
  expect_map();
  if (!node_.IsMap()) return;  // null: nothing to check
  std::vector<std::string> seen;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const YAML::Node k = it->first;  // a copy: it-> yields a temporary pair
    const std::string name = k.IsScalar() ? k.Scalar() : std::string("<non-scalar key>");
    const int line = one_based(k.Mark().line);
    const int col = one_based(k.Mark().column);
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) {
      throw ConfigError(file_, line, col, field(name), "key given twice");
    }
    seen.push_back(name);
    if (std::find(known_->begin(), known_->end(), name) != known_->end()) continue;
    std::string why = "unknown key";
    const std::string guess = closest_match(name, *known_);
    if (!guess.empty()) {
      why += "; did you mean '" + guess + "'?";
    } else if (!known_->empty()) {
      why += " (valid keys: " + join(*known_) + ")";
    }
    throw ConfigError(file_, line, col, field(name), why);
  }
}

YamlFields load_yaml_fields(const std::string& path) {
  return YamlFields(load_yaml_file(path), path, "");
}

}  // namespace hd::config
