#include "tools/geom/scenario_json.h"

#include <cmath>
#include <initializer_list>

#include "core/blend_weights.h"
#include "core/reprojection_error.h"
#include "core/view_measure.h"

namespace hd::core::cli {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& field, const std::string& what) {
  throw ScenarioError(field + ": " + what);
}

void only_keys(const json& j, const std::string& where, std::initializer_list<const char*> keys) {
  for (const auto& [k, v] : j.items()) {
    bool known = k == "name" || k == "comment";
    for (const char* key : keys) known = known || k == key;
    if (!known) fail(where + "." + k, "unknown field");
  }
}

const json& member(const json& j, const std::string& where, const char* key) {
  if (!j.contains(key)) fail(where + "." + key, "missing");
  return j.at(key);
}

double number(const json& j, const std::string& field) {
  if (!j.is_number()) fail(field, "expected a number");
  const double x = j.get<double>();
  if (!std::isfinite(x)) fail(field, "expected a finite number");
  return x;
}

double positive(const json& j, const std::string& field) {
  if (!j.is_number() || !std::isfinite(j.get<double>()) || !(j.get<double>() > 0.0))
    fail(field, "expected a positive number");
  return j.get<double>();
}

int positive_int(const json& j, const std::string& field) {
  if (!j.is_number_integer() || j.get<long long>() <= 0 || j.get<long long>() > 1'000'000)
    fail(field, "expected a positive integer (at most 1000000)");
  return static_cast<int>(j.get<long long>());
}

template <int N>
Eigen::Matrix<double, N, 1> vec(const json& j, const std::string& field) {
  if (!j.is_array() || j.size() != N)
    fail(field, "expected an array of " + std::to_string(N) + " numbers");
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = number(j[i], field + "[" + std::to_string(i) + "]");
  return v;
}

void camera(const json& j, const std::string& where, Pinhole& k, Pose& pose) {
  if (!j.is_object()) fail(where, "expected an object");
  only_keys(j, where, {"fx", "fy", "cx", "cy", "width", "height", "R", "t"});
  k.fx = positive(member(j, where, "fx"), where + ".fx");
  k.fy = positive(member(j, where, "fy"), where + ".fy");
  k.cx = number(member(j, where, "cx"), where + ".cx");
  k.cy = number(member(j, where, "cy"), where + ".cy");
  k.width = positive_int(member(j, where, "width"), where + ".width");
  k.height = positive_int(member(j, where, "height"), where + ".height");
  const auto r = vec<9>(member(j, where, "R"), where + ".R");
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) pose.R(i, c) = r[3 * i + c];  // row-major
  pose.t = vec<3>(member(j, where, "t"), where + ".t");
  if (!pose.valid(1e-6))
    fail(where + ".R", "expected a rotation matrix (orthonormal to 1e-6, determinant +1)");
}

json finite_or_null(double x) {
  return std::isfinite(x) ? json(x) : json(nullptr);
}

}  // namespace

Scenario parse_scenario(const json& j, const std::string& where) {
  if (!j.is_object()) fail(where, "expected an object");
  only_keys(j, where, {"real", "virtual", "d", "near", "workspace", "points", "blend", "pixels"});
  Scenario sc;
  ViewSetup& s = sc.setup;
  camera(member(j, where, "real"), where + ".real", s.real, s.T_world_real);
  camera(member(j, where, "virtual"), where + ".virtual", s.virt, s.T_world_virt);
  s.d_m = positive(member(j, where, "d"), where + ".d");
  s.near_m = j.contains("near") ? positive(j.at("near"), where + ".near") : 0.01;
  const std::string ws = where + ".workspace";
  const json& w = member(j, where, "workspace");
  if (!w.is_object()) fail(ws, "expected an object");
  only_keys(w, ws, {"min", "max"});
  s.workspace.min_m = vec<3>(member(w, ws, "min"), ws + ".min");
  s.workspace.max_m = vec<3>(member(w, ws, "max"), ws + ".max");
  for (int a = 0; a < 3; ++a)
    if (s.workspace.min_m[a] > s.workspace.max_m[a])
      fail(ws + ".min[" + std::to_string(a) + "]", "expected <= max on every axis");
  if (j.contains("points")) {
    const json& p = j.at("points");
    if (!p.is_array()) fail(where + ".points", "expected an array of [x,y,z]");
    for (std::size_t i = 0; i < p.size(); ++i)
      sc.points.push_back(vec<3>(p[i], where + ".points[" + std::to_string(i) + "]"));
  }
  if (j.contains("blend")) {
    const std::string bw = where + ".blend";
    const json& b = j.at("blend");
    if (!b.is_object()) fail(bw, "expected an object");
    only_keys(b, bw, {"m_t", "eps"});
    if (b.contains("m_t")) sc.m_t = number(b.at("m_t"), bw + ".m_t");
    if (b.contains("eps")) {
      sc.eps = number(b.at("eps"), bw + ".eps");
      if (sc.eps < 0.0) fail(bw + ".eps", "expected a non-negative number");
    }
  }
  if (j.contains("pixels")) {
    const json& p = j.at("pixels");
    if (!p.is_array()) fail(where + ".pixels", "expected an array of [u,v]");
    for (std::size_t i = 0; i < p.size(); ++i)
      sc.pixels.push_back(vec<2>(p[i], where + ".pixels[" + std::to_string(i) + "]"));
  }
  return sc;
}

json evaluate_scenario(const Scenario& sc) {
  const ViewSetup& s = sc.setup;
  const ViewMeasure vm = measure_view(s);
  json out = json::object();
  json e = json::array();
  for (const auto& X : sc.points) {
    const auto err = reprojection_error(s, X);
    e.push_back(err ? finite_or_null(*err) : json(nullptr));
  }
  out["E"] = e;
  out["E_max"] = finite_or_null(vm.e_max_px);
  out["coverage"] = vm.coverage;
  out["m"] = finite_or_null(vm.m);
  out["update_region"] =
      vm.has_region
          ? json::array({vm.region.u_min, vm.region.v_min, vm.region.u_max, vm.region.v_max})
          : json(nullptr);
  const double w_video = video_weight(vm.m, sc.m_t, sc.eps);
  const double kappa = 1.0 - w_video;
  out["w_video"] = w_video;
  out["kappa"] = kappa;
  json w2 = json::array();
  json w2c = json::array();
  for (const auto& p : sc.pixels) {
    w2.push_back(pixel_weight(kappa, p.x(), p.y(), s.real.width, s.real.height));
    w2c.push_back(continuous_pixel_weight(w_video, p.x(), p.y(), s.real.width, s.real.height));
  }
  out["w2"] = w2;
  out["w2_continuous"] = w2c;
  return out;
}

}  // namespace hd::core::cli
