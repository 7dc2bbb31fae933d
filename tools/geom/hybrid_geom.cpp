// hybrid-geom: the per-frame geometry as a what-if tool (DESIGN.md "What we ship").
// JSON scenario(s) in (file or stdin), JSON result(s) out; malformed input: exit 2, stdout empty.

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>
#include <sstream>

#include "tools/geom/scenario_json.h"

namespace {

constexpr int kExitBadInput = 2;

const char* const kDescription =
    R"(hybrid-geom: E, E_max, coverage, m, update region and blend weights for one
real camera against the operator's virtual camera (see docs/geometry.md).

Input: one scenario object or an array of them, e.g.
  {"real":    {"fx":2000,"fy":2000,"cx":800,"cy":600,"width":1600,"height":1200,
               "R":[1,0,0, 0,1,0, 0,0,1], "t":[0,0,0]},
   "virtual": {"fx":1000,"fy":1000,"cx":400,"cy":300,"width":800,"height":600,
               "R":[1,0,0, 0,1,0, 0,0,1], "t":[0.02,0,0]},
   "d": 0.5, "near": 0.01,
   "workspace": {"min":[-0.5,-0.5,0.2], "max":[0.5,0.5,1.0]},
   "points": [[0,0,1.0]], "blend": {"m_t": 40, "eps": 10}, "pixels": [[800,600]]}
R is row-major camera-to-world, t the camera centre (metres); near defaults to 0.01;
points, blend (m_t 40, eps 10) and pixels (real image positions) are optional.
Output: {"E":[...],"E_max","coverage","m","update_region":[umin,vmin,umax,vmax],
         "w_video","kappa","w2":[...],"w2_continuous":[...]}; infinite/undefined values are null.
Exit codes: 0 ok, 2 malformed input (message on stderr naming the field, nothing on stdout).)";

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kDescription, "hybrid-geom"};
  std::string path = "-";
  int indent = -1;
  app.add_option("input", path, "scenario JSON file; '-' or none reads stdin");
  app.add_option("--indent", indent, "pretty-print with this many spaces (default: one line)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  std::string text;
  const std::string source = path == "-" ? std::string("<stdin>") : path;
  if (path == "-") {
    std::ostringstream ss;
    ss << std::cin.rdbuf();
    text = ss.str();
  } else {
    std::ifstream f(path, std::ios::binary);
    if (!f) {
      std::cerr << "hybrid-geom: " << path << ": cannot open\n";
      return kExitBadInput;
    }
    std::ostringstream ss;
    ss << f.rdbuf();
    text = ss.str();
  }

  nlohmann::json in;
  try {
    in = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    std::cerr << "hybrid-geom: " << source << ": invalid JSON: " << e.what() << "\n";
    return kExitBadInput;
  }

  // Parse everything before printing anything, so bad input leaves stdout empty.
  try {
    nlohmann::json out;
    if (in.is_array()) {
      std::vector<hd::core::cli::Scenario> all;
      for (std::size_t i = 0; i < in.size(); ++i)
        all.push_back(hd::core::cli::parse_scenario(in[i], "scenario[" + std::to_string(i) + "]"));
      out = nlohmann::json::array();
      for (const auto& sc : all) out.push_back(hd::core::cli::evaluate_scenario(sc));
    } else {
      out = hd::core::cli::evaluate_scenario(hd::core::cli::parse_scenario(in, "scenario"));
    }
    std::cout << out.dump(indent) << "\n";
  } catch (const hd::core::cli::ScenarioError& e) {
    std::cerr << "hybrid-geom: " << source << ": " << e.what() << "\n";
    return kExitBadInput;
  }
  return 0;
}
