#pragma once
// hybrid-geom's JSON contract (issue #2 item 3): scenario objects in, result objects out.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/view_setup.h"

namespace hd::core::cli {

struct Scenario {
  ViewSetup setup;
  std::vector<Eigen::Vector3d> points;  ///< world points to evaluate E at
  double m_t = 40.0;
  double eps = 10.0;
  std::vector<Eigen::Vector2d> pixels;  ///< real (video) image positions for w2
};

/// A malformed field; what() names it, e.g. "scenario[1].real.fx: expected a positive number".
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses one scenario object; `where` is its name in messages ("scenario" or "scenario[3]").
Scenario parse_scenario(const nlohmann::json& j, const std::string& where);

/// Evaluates a scenario: E, E_max, coverage, m, update_region, w_video, kappa, w2, w2_continuous.
/// Infinite or undefined values are null.
nlohmann::json evaluate_scenario(const Scenario& sc);

}  // namespace hd::core::cli
