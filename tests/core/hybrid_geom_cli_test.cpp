// hybrid-geom as a program: the issue's example, arrays, stdin, and malformed input (exit 2,
// empty stdout, a message naming the field).

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include "test_paths.h"

namespace {

struct RunResult {
  int exit_code;
  std::string out;
  std::string err;
};

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// Runs hybrid-geom with `input` written to a file (args "FILE") or piped on stdin (args "-").
RunResult run(const std::string& input, bool use_stdin = false) {
  const std::string dir = ::testing::TempDir();
  const std::string tag = std::to_string(::getpid()) + "_" +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::string in = dir + "in_" + tag + ".json";
  const std::string out = dir + "out_" + tag + ".txt";
  const std::string err = dir + "err_" + tag + ".txt";
  std::ofstream(in) << input;
  const std::string cmd = std::string(hd::test::geom_bin()) + (use_stdin ? " - < " : " ") + in +
                          " > " + out + " 2> " + err;
  const int status = std::system(cmd.c_str());
  RunResult r{WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  std::remove(in.c_str());
  std::remove(out.c_str());
  std::remove(err.c_str());
  return r;
}

const char* const kExample =
    R"({"real":    {"fx":2000,"fy":2000,"cx":800,"cy":600,"width":1600,"height":1200,
             "R":[1,0,0, 0,1,0, 0,0,1], "t":[0,0,0]},
 "virtual": {"fx":1000,"fy":1000,"cx":400,"cy":300,"width":800,"height":600,
             "R":[1,0,0, 0,1,0, 0,0,1], "t":[0.02,0,0]},
 "d": 0.5, "near": 0.01,
 "workspace": {"min":[-0.5,-0.5,0.2], "max":[0.5,0.5,1.0]},
 "points": [[0,0,1.0]],
 "blend": {"m_t": 40, "eps": 10},
 "pixels": [[800,600]]})";

void expect_example(const nlohmann::json& j) {
  ASSERT_EQ(j["E"].size(), 1u);
  EXPECT_NEAR(j["E"][0].get<double>(), 20.0, 1e-9);
  EXPECT_NEAR(j["E_max"].get<double>(), 60.0, 1e-9);
  EXPECT_NEAR(j["coverage"].get<double>(), 0.95, 1e-12);
  EXPECT_NEAR(j["m"].get<double>(), 60.0 / 0.95, 1e-9);
  const auto& r = j["update_region"];
  ASSERT_EQ(r.size(), 4u);
  EXPECT_NEAR(r[0].get<double>(), 80, 1e-9);
  EXPECT_NEAR(r[1].get<double>(), 0, 1e-9);
  EXPECT_NEAR(r[2].get<double>(), 1600, 1e-9);
  EXPECT_NEAR(r[3].get<double>(), 1200, 1e-9);
  EXPECT_EQ(j["w_video"].get<double>(), 0.0);  // m = 63.2 is beyond m_t + eps = 50
  EXPECT_EQ(j["kappa"].get<double>(), 1.0);
  EXPECT_EQ(j["w2"][0].get<double>(), 1.0);  // centre pixel at kappa = 1
}

}  // namespace

TEST(HybridGeomCli, IssueExample) {
  const RunResult r = run(kExample);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_example(nlohmann::json::parse(r.out));
}

TEST(HybridGeomCli, ArrayFromStdinKeepsOrderAndWritesInfinityAsNull) {
  auto behind = nlohmann::json::parse(kExample);
  behind["virtual"]["t"] = {0, 0, 0.6};  // beyond the plane: E = inf, C = 0
  behind["workspace"]["min"] = {-0.5, -0.5, 0.7};
  behind["points"] = {{0, 0, 0.9}, {0, 0, -1}};
  const nlohmann::json arr = {nlohmann::json::parse(kExample), behind};
  const RunResult r = run(arr.dump(), true);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  expect_example(j[0]);
  EXPECT_TRUE(j[1]["E"][0].is_null());  // X'' behind the virtual camera: +inf
  EXPECT_TRUE(j[1]["E"][1].is_null());  // X behind the cameras: undefined
  EXPECT_TRUE(j[1]["E_max"].is_null());
  EXPECT_TRUE(j[1]["m"].is_null());
  EXPECT_TRUE(j[1]["update_region"].is_null());
  EXPECT_EQ(j[1]["coverage"].get<double>(), 0.0);
}

TEST(HybridGeomCli, MalformedFieldNamedExitTwoNothingOnStdout) {
  auto bad = nlohmann::json::parse(kExample);
  bad["real"]["fx"] = -3;
  const nlohmann::json arr = {nlohmann::json::parse(kExample), bad};
  const RunResult r = run(arr.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("scenario[1].real.fx: expected a positive number"), std::string::npos)
      << r.err;
}

TEST(HybridGeomCli, OtherMalformedInputs) {
  struct Case {
    const char* path;
    nlohmann::json value;
    const char* message;
  };
  const Case cases[] = {
      {"/virtual/R", {1, 0, 0, 0, 1, 0, 0, 0, 2}, "scenario.virtual.R: expected a rotation"},
      {"/virtual/width", 12.5, "scenario.virtual.width: expected a positive integer"},
      {"/d", "half", "scenario.d: expected a positive number"},
      {"/workspace/min", {0, 0, 2.0}, "scenario.workspace.min[2]: expected <= max"},
      {"/points/0", {0, 0}, "scenario.points[0]: expected an array of 3 numbers"},
      {"/blend/eps", -1, "scenario.blend.eps: expected a non-negative number"},
      {"/nera", 0.1, "scenario.nera: unknown field"},
  };
  for (const auto& c : cases) {
    auto j = nlohmann::json::parse(kExample);
    j[nlohmann::json::json_pointer(c.path)] = c.value;
    const RunResult r = run(j.dump());
    EXPECT_EQ(r.exit_code, 2) << c.path;
    EXPECT_TRUE(r.out.empty()) << c.path;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.path << ": " << r.err;
  }
  auto j = nlohmann::json::parse(kExample);
  j.erase("real");
  RunResult r = run(j.dump());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("scenario.real: missing"), std::string::npos) << r.err;
  r = run("{\"real\": ");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("invalid JSON"), std::string::npos) << r.err;
}

TEST(HybridGeomCli, HelpExitsZero) {
  const std::string cmd = std::string(hd::test::geom_bin()) + " --help > /dev/null";
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}
