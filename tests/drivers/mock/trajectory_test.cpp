#include "drivers/mock/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace hd::drivers {
namespace {

std::string error_of(const std::string& csv) {
  std::istringstream in(csv);
  try {
    Trajectory::parse_csv(in, "walk.csv");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(Trajectory, ParsesHeaderCommentsAndInterpolates) {
  const double c = std::cos(std::numbers::pi / 4), s = std::sin(std::numbers::pi / 4);
  std::istringstream in("t_s,x,y,z,qw,qx,qy,qz\n# start\n0, 0,0,0, 1,0,0,0\n\n1, 2,0,-4, " +
                        std::to_string(c) + ",0,0," + std::to_string(s) + "\n");
  const Trajectory t = Trajectory::parse_csv(in, "walk.csv");
  ASSERT_EQ(t.samples().size(), 2u);
  EXPECT_DOUBLE_EQ(t.duration_s(), 1.0);
  const TrajectorySample mid = t.at(0.5);
  EXPECT_TRUE(mid.position_m.isApprox(Eigen::Vector3d(1, 0, -2)));
  // Halfway between identity and 90 degrees about z: 45 degrees about z.
  const Eigen::AngleAxisd aa(mid.q);
  EXPECT_NEAR(aa.angle(), std::numbers::pi / 4, 1e-5);
  EXPECT_TRUE(aa.axis().isApprox(Eigen::Vector3d::UnitZ(), 1e-6));
  // Clamped outside the time range.
  EXPECT_TRUE(t.at(-3).position_m.isZero());
  EXPECT_TRUE(t.at(7).position_m.isApprox(Eigen::Vector3d(2, 0, -4)));
}

TEST(Trajectory, BadLinesAreNamedWithFileLineAndField) {
  EXPECT_EQ(error_of("0,0,0,0,1,0,0,0\n1,0,0\n"),
            "walk.csv:2: expected 8 fields (t_s, x, y, z, qw, qx, qy, qz), got 3");
  EXPECT_EQ(error_of("0,0,0,0,1,abc,0,0\n"),
            "walk.csv:1: field qx is \"abc\", expected a finite number");
  EXPECT_EQ(error_of("0,0,0,nan,1,0,0,0\n"),
            "walk.csv:1: field z is \"nan\", expected a finite number");
  EXPECT_NE(error_of("0,0,0,0,1,0,0,0\n0,0,0,0,1,0,0,0\n").find("walk.csv:2: t_s 0 is not after"),
            std::string::npos);
  EXPECT_NE(
      error_of("0,0,0,0,2,0,0,0\n").find("walk.csv:1: quaternion (qw, qx, qy, qz) has norm 2"),
      std::string::npos);
  EXPECT_EQ(error_of("# nothing\n"), "walk.csv: no trajectory samples");
}

TEST(Trajectory, MissingFileIsNamed) {
  try {
    Trajectory::load_csv("/nonexistent/walk.csv");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/walk.csv"), std::string::npos);
  }
}

}  // namespace
}  // namespace hd::drivers
