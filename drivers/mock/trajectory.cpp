#include "drivers/mock/trajectory.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace hd::drivers {
namespace {

constexpr const char* kColumns[] = {"t_s", "x", "y", "z", "qw", "qx", "qy", "qz"};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

}  // namespace

Trajectory::Trajectory(std::vector<TrajectorySample> samples) : samples_(std::move(samples)) {
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    if (!std::isfinite(samples_[i].t_s) || (i > 0 && !(samples_[i].t_s > samples_[i - 1].t_s)))
      throw std::runtime_error("trajectory: sample " + std::to_string(i) +
                               ": times must be finite and strictly increasing");
    samples_[i].q.normalize();
  }
}

Trajectory Trajectory::parse_csv(std::istream& in, const std::string& name) {
  std::vector<TrajectorySample> out;
  std::string line;
  int line_no = 0;
  bool seen_data = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    std::vector<std::string> fields;
    std::stringstream ss(t);
    std::string f;
    while (std::getline(ss, f, ',')) fields.push_back(trim(f));
    if (!seen_data && !fields.empty() && fields[0] == "t_s") continue;  // header
    seen_data = true;
    if (fields.size() != 8)
      throw std::runtime_error(where + "expected 8 fields (t_s, x, y, z, qw, qx, qy, qz), got " +
                               std::to_string(fields.size()));
    double v[8];
    for (int i = 0; i < 8; ++i) {
      const char* s = fields[static_cast<std::size_t>(i)].c_str();
      char* end = nullptr;
      errno = 0;
      v[i] = std::strtod(s, &end);
      if (end == s || *end != '\0' || errno == ERANGE || !std::isfinite(v[i]))
        throw std::runtime_error(where + "field " + kColumns[i] + " is \"" +
                                 fields[static_cast<std::size_t>(i)] +
                                 "\", expected a finite number");
    }
    TrajectorySample s;
    s.t_s = v[0];
    s.position_m = {v[1], v[2], v[3]};
    s.q = Eigen::Quaterniond(v[4], v[5], v[6], v[7]);
    const double n = s.q.norm();
    if (std::fabs(n - 1.0) > 1e-3)
      throw std::runtime_error(where + "quaternion (qw, qx, qy, qz) has norm " + std::to_string(n) +
                               ", expected 1");
    s.q.normalize();
    if (!out.empty() && !(s.t_s > out.back().t_s))
      throw std::runtime_error(where + "t_s " + fields[0] + " is not after the previous line's " +
                               std::to_string(out.back().t_s));
    out.push_back(s);
  }
  if (out.empty()) throw std::runtime_error(name + ": no trajectory samples");
  return Trajectory(std::move(out));
}

Trajectory Trajectory::load_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open trajectory file");
  return parse_csv(in, path);
}

double Trajectory::duration_s() const {
  return samples_.empty() ? 0.0 : samples_.back().t_s - samples_.front().t_s;
}

TrajectorySample Trajectory::at(double t_s) const {
  if (samples_.empty()) return {};
  if (!(t_s > samples_.front().t_s)) return samples_.front();
  if (t_s >= samples_.back().t_s) return samples_.back();
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t_s,
                                   [](double t, const TrajectorySample& s) { return t < s.t_s; });
  const TrajectorySample& b = *it;
  const TrajectorySample& a = *(it - 1);
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  TrajectorySample s;
  s.t_s = t_s;
  s.position_m = (1 - u) * a.position_m + u * b.position_m;
  s.q = a.q.slerp(u, b.q);
  return s;
}

}  // namespace hd::drivers
