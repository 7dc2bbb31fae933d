// The undistorter against OpenCV: its fixed-point kernel against cv::remap on the same maps, and
// the geometry against cv::undistortPoints (a second method) on a rendered grid of dots.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "station/video/frame_copy.h"
#include "station/video/undistorter.h"

namespace hd::station {
namespace {

core::Pinhole distorted_camera(int w, int h, double f, std::array<double, 5> k) {
  core::Pinhole p = core::Pinhole::centred(f, w, h);
  p.cx += 3.25;  // principal point off-centre, so a swapped or mis-shifted axis shows
  p.cy -= 2.5;
  for (std::size_t i = 0; i < 5; ++i) p.distortion[i] = k[i];
  p.distortion_count = 5;
  return p;
}

// OpenCV's camera matrix: its pixel centres are at integers, the project's at +0.5.
cv::Matx33d cv_k(const core::Pinhole& p) {
  return {p.fx, 0, p.cx - 0.5, 0, p.fy, p.cy - 0.5, 0, 0, 1};
}
cv::Mat cv_d(const core::Pinhole& p) {
  cv::Mat d(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) d.at<double>(i) = p.distortion[static_cast<std::size_t>(i)];
  return d;
}

TEST(VideoUndistorter, KernelEqualsCvRemapOnTheSameFixedPointMaps) {
  const core::Pinhole p = distorted_camera(97, 61, 70.0, {0.3, 0.1, 0.001, -0.002, 0.01});
  drivers::Frame src, dst;
  src.allocate_rgba(p.width, p.height);
  dst.allocate_rgba(p.width, p.height);
  std::mt19937 rng(7);
  for (auto& b : src.data) b = static_cast<uint8_t>(rng());
  const Undistorter u(p);
  ASSERT_TRUE(u.apply(src, dst));

  cv::Mat map1, map2, ref;
  cv::initUndistortRectifyMap(cv_k(p), cv_d(p), cv::noArray(), cv_k(p), {p.width, p.height},
                              CV_16SC2, map1, map2);
  const cv::Mat s(p.height, p.width, CV_8UC4, src.data.data(),
                  static_cast<std::size_t>(src.stride_bytes));
  cv::remap(s, ref, map1, map2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  int max_diff = 0, border_pixels = 0;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      for (int c = 0; c < 4; ++c)
        max_diff = std::max(
            max_diff, std::abs(int{dst.data[static_cast<std::size_t>((y * p.width + x) * 4 + c)]} -
                               int{ref.at<cv::Vec4b>(y, x)[c]}));
      border_pixels += ref.at<cv::Vec4b>(y, x)[3] == 0;
    }
  EXPECT_LE(max_diff, 1);
  RecordProperty("max_diff_vs_cv_remap",
                 max_diff);     // same maps, same weights: at most a rounding step apart
  EXPECT_GT(border_pixels, 0);  // pincushion: the corners sample outside the frame (border)
}

struct Dot {
  double u, v;  // continuous pixel coordinates (centres at +0.5)
};

TEST(VideoUndistorter, GridOfDotsLandsWhereUndistortPointsSays) {
  const core::Pinhole p = distorted_camera(640, 480, 520.0, {-0.28, 0.09, 0.0006, -0.0008, 0.0});
  // Dots placed on the distorted image; where they must appear after undistortion comes from
  // cv::undistortPoints (iterative inversion of the model), independently of the remap maps.
  std::vector<cv::Point2d> distorted_cv;
  for (int gy = 0; gy < 9; ++gy)
    for (int gx = 0; gx < 12; ++gx) distorted_cv.emplace_back(30.0 + gx * 52.3, 28.0 + gy * 52.9);
  std::vector<cv::Point2d> undistorted_cv;
  cv::undistortPoints(
      distorted_cv, undistorted_cv, cv_k(p), cv_d(p), cv::noArray(), cv_k(p),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));

  // Gaussian dots (sigma 1.6 px) rendered at the distorted positions, sampled at pixel centres.
  drivers::Frame src, dst;
  src.allocate_rgba(p.width, p.height);
  dst.allocate_rgba(p.width, p.height);
  const double sigma = 1.6;
  for (const cv::Point2d& d : distorted_cv) {
    const double cu = d.x + 0.5, cv_ = d.y + 0.5;
    for (int y = static_cast<int>(cv_) - 8; y <= static_cast<int>(cv_) + 8; ++y)
      for (int x = static_cast<int>(cu) - 8; x <= static_cast<int>(cu) + 8; ++x) {
        if (x < 0 || y < 0 || x >= p.width || y >= p.height) continue;
        const double r2 = (x + 0.5 - cu) * (x + 0.5 - cu) + (y + 0.5 - cv_) * (y + 0.5 - cv_);
        uint8_t* px = src.data.data() + static_cast<std::size_t>((y * p.width + x) * 4);
        const int value = std::max<int>(
            px[1], static_cast<int>(std::lround(250.0 * std::exp(-r2 / (2 * sigma * sigma)))));
        px[0] = px[1] = px[2] = static_cast<uint8_t>(value);
        px[3] = 255;
      }
  }
  const Undistorter und(p);
  ASSERT_TRUE(und.apply(src, dst));

  int checked = 0;
  double worst = 0.0;
  for (const cv::Point2d& e_cv : undistorted_cv) {
    const Dot expect{e_cv.x + 0.5, e_cv.y + 0.5};
    if (expect.u < 12 || expect.v < 12 || expect.u > p.width - 12 || expect.v > p.height - 12)
      continue;
    // Intensity-weighted centroid in a window around the expected place.
    double sw = 0, su = 0, sv = 0;
    for (int y = static_cast<int>(expect.v) - 7; y <= static_cast<int>(expect.v) + 7; ++y)
      for (int x = static_cast<int>(expect.u) - 7; x <= static_cast<int>(expect.u) + 7; ++x) {
        const double w = dst.data[static_cast<std::size_t>((y * p.width + x) * 4 + 1)];
        sw += w;
        su += w * (x + 0.5);
        sv += w * (y + 0.5);
      }
    ASSERT_GT(sw, 100.0) << "no dot near " << expect.u << "," << expect.v;
    const double err = std::hypot(su / sw - expect.u, sv / sw - expect.v);
    worst = std::max(worst, err);
    EXPECT_LT(err, 0.3) << "dot expected at " << expect.u << "," << expect.v;
    ++checked;
  }
  EXPECT_GE(checked, 80);
  // The distortion is strong enough that skipping undistortion would fail the same check.
  double moved = 0.0;
  for (std::size_t i = 0; i < distorted_cv.size(); ++i)
    moved = std::max(moved, cv::norm(distorted_cv[i] - undistorted_cv[i]));
  EXPECT_GT(moved, 10.0);
  RecordProperty("worst_dot_error_px", std::to_string(worst));
}

TEST(VideoUndistorter, SourceOfAgreesWithDistortingTheOutputRay) {
  const core::Pinhole p = distorted_camera(320, 240, 260.0, {-0.2, 0.05, 0.001, 0.0005, 0.0});
  const Undistorter u(p);
  // Output pixel centre -> its ray -> cv::projectPoints with the distortion: the map's source,
  // to the map's 1/32 px resolution.
  for (int y = 0; y < p.height; y += 37)
    for (int x = 0; x < p.width; x += 41) {
      const Eigen::Vector3d r = p.ray({x + 0.5, y + 0.5});
      std::vector<cv::Point3d> obj{{r.x(), r.y(), 1.0}};
      std::vector<cv::Point2d> img;
      cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv_k(p), cv_d(p), img);
      double su = 0, sv = 0;
      u.source_of(x, y, su, sv);
      EXPECT_NEAR(su, img[0].x + 0.5, 1.0 / 32 + 1e-3) << x << "," << y;
      EXPECT_NEAR(sv, img[0].y + 0.5, 1.0 / 32 + 1e-3) << x << "," << y;
    }
}

TEST(VideoUndistorter, NeededOnlyForNonZeroCoefficients) {
  core::Pinhole p = core::Pinhole::centred(100, 64, 48);
  EXPECT_FALSE(Undistorter::needed(p));
  p.distortion_count = 5;
  EXPECT_FALSE(Undistorter::needed(p));  // calibrated as exactly zero
  p.distortion[3] = 1e-4;
  EXPECT_TRUE(Undistorter::needed(p));
  p.distortion_count = 2;  // a coefficient beyond the calibrated count is not part of the model
  EXPECT_FALSE(Undistorter::needed(p));
}

TEST(VideoUndistorter, MismatchedFramesAreRejectedAndLeftUntouched) {
  const core::Pinhole p = distorted_camera(64, 48, 60.0, {-0.1, 0, 0, 0, 0});
  const Undistorter u(p);
  drivers::Frame src, dst;
  src.allocate_rgba(64, 48);
  dst.allocate_rgba(64, 48);
  std::fill(dst.data.begin(), dst.data.end(), uint8_t{9});
  src.sequence = 42;
  src.host_timestamp_ns = 123;

  drivers::Frame small;
  small.allocate_rgba(32, 48);
  EXPECT_FALSE(u.apply(small, dst));
  drivers::Frame yuyv = src;
  yuyv.format = drivers::PixelFormat::kYuyv;
  EXPECT_FALSE(u.apply(yuyv, dst));
  drivers::Frame short_buffer = src;
  short_buffer.data.resize(100);
  EXPECT_FALSE(u.apply(short_buffer, dst));
  for (uint8_t b : dst.data) ASSERT_EQ(b, 9);
  EXPECT_EQ(dst.sequence, 0u);

  ASSERT_TRUE(u.apply(src, dst));
  EXPECT_EQ(dst.sequence, 42u);
  EXPECT_EQ(dst.host_timestamp_ns, 123);
  core::Pinhole bad = p;
  bad.fx = -1;
  EXPECT_THROW(Undistorter{bad}, std::invalid_argument);
}

TEST(VideoFrameCopy, CopiesPixelsAcrossStridesAndKeepsStamps) {
  drivers::Frame a, b;
  a.allocate_rgba(5, 3);
  b.width = 5;
  b.height = 3;
  b.stride_bytes = 24;  // padded rows
  b.data.assign(24 * 3, 0);
  for (std::size_t i = 0; i < a.data.size(); ++i) a.data[i] = static_cast<uint8_t>(i + 1);
  a.sequence = 5;
  a.device_timestamp_ns = 77;
  a.host_timestamp_ns = 99;
  a.device_time_trusted = true;
  a.link = {101, 102, 103, 104};  // a network camera's stages: the HUD's and latency.png's
  ASSERT_TRUE(copy_frame(a, b));
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 20; ++x)
      EXPECT_EQ(b.data[static_cast<std::size_t>(y * 24 + x)],
                a.data[static_cast<std::size_t>(y * 20 + x)]);
  EXPECT_EQ(b.data[20], 0);  // padding untouched
  EXPECT_EQ(b.sequence, 5u);
  EXPECT_EQ(b.device_timestamp_ns, 77);
  EXPECT_EQ(b.host_timestamp_ns, 99);
  EXPECT_TRUE(b.device_time_trusted);
  EXPECT_EQ(b.link.encoded_ns, 101);
  EXPECT_EQ(b.link.sent_ns, 102);
  EXPECT_EQ(b.link.received_ns, 103);
  EXPECT_EQ(b.link.decoded_ns, 104);
}

}  // namespace
}  // namespace hd::station
