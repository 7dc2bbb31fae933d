// recon's pixel-centre conversion (core::Pinhole: centres at +0.5; OpenCV: at integers): the
// round trip, and OpenCV's own projection against core's.

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <vector>

#include "recon/opencv_camera.h"

namespace {

using hd::core::Pinhole;
using namespace hd::recon;

TEST(OpencvCamera, RoundTripKeepsEveryParameter) {
  Pinhole p = Pinhole::centred(523.5, 640, 480);
  p.fy = 519.25;
  p.cx = 321.75;
  p.distortion_count = 5;
  p.distortion = {-0.12, 0.03, 0.001, -0.002, 0.0005, 0, 0, 0};
  const cv::Matx33d K = opencv_camera_matrix(p);
  EXPECT_DOUBLE_EQ(K(0, 2), 321.25);
  EXPECT_DOUBLE_EQ(K(1, 2), 239.5);
  const Pinhole q = pinhole_from_opencv(K, opencv_distortion(p), p.width, p.height);
  EXPECT_DOUBLE_EQ(q.fx, p.fx);
  EXPECT_DOUBLE_EQ(q.fy, p.fy);
  EXPECT_DOUBLE_EQ(q.cx, p.cx);
  EXPECT_DOUBLE_EQ(q.cy, p.cy);
  EXPECT_EQ(q.distortion_count, 5);
  for (int i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(q.distortion[i], p.distortion[i]);
  EXPECT_TRUE(opencv_distortion(Pinhole::centred(500, 64, 48)).empty());
  EXPECT_THROW(pinhole_from_opencv(K, cv::Mat::zeros(1, 3, CV_64F), 640, 480),
               std::invalid_argument);
}

TEST(OpencvCamera, OpencvProjectsHalfAPixelLeftAndUpOfCore) {
  const Pinhole p = Pinhole::centred(500, 640, 480);
  const std::vector<cv::Point3d> X = {{0.1, -0.2, 1.5}, {-0.4, 0.3, 2.0}, {0, 0, 1}};
  std::vector<cv::Point2d> uv;
  cv::projectPoints(X, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), opencv_camera_matrix(p),
                    opencv_distortion(p), uv);
  for (std::size_t i = 0; i < X.size(); ++i) {
    const Eigen::Vector2d c = p.project({X[i].x, X[i].y, X[i].z});
    EXPECT_NEAR(uv[i].x, c.x() - 0.5, 1e-9);
    EXPECT_NEAR(uv[i].y, c.y() - 0.5, 1e-9);
  }
}

}  // namespace
