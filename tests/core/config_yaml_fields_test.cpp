// The checked YAML reader: each kind of mistake is reported at the line and field where it is.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/config/yaml_fields.h"

namespace hd::config {
namespace {

YamlFields parse(const std::string& text) {
  return YamlFields(parse_yaml(text, "t.yaml"), "t.yaml");
}

/// Runs `read` and returns the ConfigError it throws (fails the test if none).
template <typename F>
ConfigError error_of(F read) {
  try {
    read();
  } catch (const ConfigError& e) {
    return e;
  }
  ADD_FAILURE() << "no ConfigError";
  return ConfigError("", 0, 0, "", "none");
}

TEST(YamlFields, ReadsValuesOfEveryKind) {
  const YamlFields f = parse(
      "a: 1.5\n"
      "n: 7\n"
      "flag: true\n"
      "name: cam0\n"
      "v: [1, -2, 3.25]\n"
      "mode: hybrid\n"
      "inner:\n"
      "  x: 2\n"
      "items:\n"
      "  - 4\n"
      "  - 5\n");
  EXPECT_DOUBLE_EQ(f.required_double("a"), 1.5);
  EXPECT_EQ(f.required_int("n"), 7);
  EXPECT_TRUE(f.required_bool("flag"));
  EXPECT_EQ(f.required_string("name"), "cam0");
  EXPECT_EQ(f.required_vec3("v"), Eigen::Vector3d(1, -2, 3.25));
  EXPECT_EQ(f.required_enum("mode", {"video", "hybrid", "synthetic"}), 1u);
  EXPECT_DOUBLE_EQ(f.required_map("inner").required_double("x"), 2.0);
  const auto items = f.required_list("items", 2);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_EQ(items[1].as_int(), 5);
  EXPECT_EQ(items[1].path(), "items[1]");
  EXPECT_DOUBLE_EQ(f.optional_double("absent", 9.0), 9.0);
  EXPECT_EQ(f.optional_string("absent2", "d"), "d");
  EXPECT_NO_THROW(f.finish());
}

TEST(YamlFields, MissingKeyNamesTheMappingLineAndField) {
  const YamlFields f = parse("top: 1\ncam:\n  fx: 500\n  fy: 500\n");
  const ConfigError e = error_of([&] { f.required_map("cam").required_double("cx"); });
  EXPECT_EQ(e.file(), "t.yaml");
  EXPECT_EQ(e.line(), 3);  // the mapping's first key
  EXPECT_EQ(e.field(), "cam.cx");
  EXPECT_NE(std::string(e.what()).find("t.yaml:3:3: cam.cx: missing required key"),
            std::string::npos)
      << e.what();
}

TEST(YamlFields, WrongTypeAndRangeAreReportedAtTheValue) {
  const YamlFields f = parse("a: 1\nb: hello\nc: -2\nd: [1, 2]\ne: .nan\n");
  ConfigError e = error_of([&] { f.required_double("b"); });
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 4);
  EXPECT_EQ(e.field(), "b");
  EXPECT_NE(e.why().find("expected a number"), std::string::npos);
  e = error_of([&] { f.required_double("c", Range::positive()); });
  EXPECT_EQ(e.line(), 3);
  EXPECT_NE(e.why().find("out of range: must be > 0"), std::string::npos) << e.why();
  e = error_of([&] { f.required_vec3("d"); });
  EXPECT_EQ(e.line(), 4);
  EXPECT_NE(e.why().find("list of 3 numbers"), std::string::npos);
  e = error_of([&] { f.required_double("e"); });  // NaN is never a valid setting
  EXPECT_EQ(e.line(), 5);
  e = error_of([&] { f.required_int("a", Range::closed(2, 4)); });
  EXPECT_NE(e.why().find("in [2, 4]"), std::string::npos);
  e = error_of([&] { parse("x: 1.5\n").required_int("x"); });
  EXPECT_NE(e.why().find("integer"), std::string::npos);
}

TEST(YamlFields, ListsOfSomeNumbersCheckTheirLengthAndEachItem) {
  const YamlFields f = parse("k: [0, 1, 2]\nshort: [1]\nbad: [1, x]\n");
  EXPECT_EQ(f.required_doubles("k", 2, 12), (std::vector<double>{0, 1, 2}));
  ConfigError e = error_of([&] { f.required_doubles("short", 2, 12); });
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.field(), "short");
  EXPECT_EQ(e.why(), "expected a list of 2 to 12 numbers, got a list of 1");
  e = error_of([&] { f.required_doubles("bad", 2, 2); });
  EXPECT_EQ(e.field(), "bad[1]");
  EXPECT_EQ(e.column(), 10);
  EXPECT_EQ(e.why(), "expected a number, got 'x'");
  e = error_of([&] { f.required_doubles("k", 2, 2); });
  EXPECT_EQ(e.why(), "expected a list of 2 numbers, got a list of 3");
}

TEST(YamlFields, ListItemFieldPathCarriesTheIndex) {
  const YamlFields f = parse("cameras:\n  - fx: 1\n  - fx: 0\n");
  const auto cams = f.required_list("cameras");
  const ConfigError e = error_of([&] { cams[1].required_double("fx", Range::positive()); });
  EXPECT_EQ(e.field(), "cameras[1].fx");
  EXPECT_EQ(e.line(), 3);
}

TEST(YamlFields, UnknownKeySuggestsTheClosestValidOne) {
  const YamlFields f = parse("position: [0, 0, 0]\npositon: [1, 1, 1]\n");
  f.required_vec3("position");
  const ConfigError e = error_of([&] { f.finish(); });
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.field(), "positon");
  EXPECT_NE(e.why().find("did you mean 'position'"), std::string::npos) << e.why();
  // Far from every valid key: the valid keys are listed instead of a guess.
  const YamlFields g = parse("position: [0, 0, 0]\nzebra: 1\n");
  g.required_vec3("position");
  const ConfigError e2 = error_of([&] { g.finish(); });
  EXPECT_NE(e2.why().find("valid keys: position"), std::string::npos) << e2.why();
}

TEST(YamlFields, DuplicateKeyIsRejected) {
  const YamlFields f = parse("a: 1\nb: 2\na: 3\n");
  f.required_double("a");
  f.required_double("b");
  const ConfigError e = error_of([&] { f.finish(); });
  EXPECT_EQ(e.line(), 3);
  EXPECT_NE(e.why().find("twice"), std::string::npos);
}

TEST(YamlFields, EnumOutsideTheListSuggests) {
  const ConfigError e = error_of([&] {
    parse("mode: hybird\n").required_enum("mode", {"video", "hybrid"});
  });
  EXPECT_NE(e.why().find("did you mean 'hybrid'"), std::string::npos) << e.why();
}

TEST(YamlFields, SyntaxErrorGivesItsLine) {
  const ConfigError e = error_of([&] { parse_yaml("a: 1\nb: [1, 2\nc: 3\n", "bad.yaml"); });
  EXPECT_EQ(e.file(), "bad.yaml");
  EXPECT_GE(e.line(), 2);  // yaml-cpp notices the unclosed list on line 2 or where it ends
  EXPECT_LE(e.line(), 4);
  EXPECT_NE(e.why().find("syntax"), std::string::npos);
  const ConfigError e2 = error_of([&] { parse_yaml("a: 1\n  b: 2\n", "bad.yaml"); });
  EXPECT_EQ(e2.line(), 2);
}

TEST(YamlFields, UnreadableFileIsNamed) {
  const ConfigError e = error_of([&] { load_yaml_file("/nonexistent/dir/x.yaml"); });
  EXPECT_EQ(e.file(), "/nonexistent/dir/x.yaml");
  EXPECT_EQ(e.line(), 0);
  EXPECT_EQ(std::string(e.what()).rfind("/nonexistent/dir/x.yaml: cannot read", 0), 0u) << e.what();
}

TEST(YamlFields, PathsResolveAgainstTheFilesDirectory) {
  const auto dir = std::filesystem::temp_directory_path() / "hd_yaml_fields_test";
  std::filesystem::create_directories(dir);
  const auto file = dir / "s.yaml";
  std::ofstream(file) << "tex: img/a.png\nabs: /x/y.png\n";
  const YamlFields f = load_yaml_fields(file.string());
  EXPECT_EQ(f.required_path("tex"), (dir / "img/a.png").string());
  EXPECT_EQ(f.required_path("abs"), "/x/y.png");
  std::filesystem::remove_all(dir);
}

TEST(YamlFields, ClosestMatchIgnoresFarWords) {
  EXPECT_EQ(closest_match("fxx", {"fx", "fy", "cx"}), "fx");
  EXPECT_EQ(closest_match("k", {"position", "rate_hz"}), "");
  EXPECT_EQ(closest_match("RATE_HZ", {"rate_hz"}), "rate_hz");
  EXPECT_EQ(closest_match("rate", {"position", "rate_hz"}), "rate_hz");  // unit suffix forgotten
}

}  // namespace
}  // namespace hd::config
