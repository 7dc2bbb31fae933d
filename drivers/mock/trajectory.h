#pragma once
// A head trajectory: timed poses read from CSV (t_s, x, y, z, qw, qx, qy, qz) and sampled at any
// time by linear / spherical interpolation.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <istream>
#include <string>
#include <vector>

namespace hd::drivers {

struct TrajectorySample {
  double t_s = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  ///< head (station axes) to tracker
};

class Trajectory {
 public:
  Trajectory() = default;
  /// Samples must be in strictly increasing time with unit quaternions (throws otherwise).
  explicit Trajectory(std::vector<TrajectorySample> samples);

  /// Reads CSV. Blank lines and lines starting with '#' are skipped, as is a first line that
  /// names the columns. Throws std::runtime_error "<name>:<line>: <what>" on the first bad line.
  static Trajectory parse_csv(std::istream& in, const std::string& name);
  static Trajectory load_csv(const std::string& path);

  /// Pose at time t (clamped to the first/last sample).
  TrajectorySample at(double t_s) const;
  double duration_s() const;
  const std::vector<TrajectorySample>& samples() const { return samples_; }

 private:
  std::vector<TrajectorySample> samples_;
};

}  // namespace hd::drivers
