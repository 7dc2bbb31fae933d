// Known cameras: does the tool recover them, and are its reported sigmas honest?
#include <opencv2/calib3d.hpp>

#include "calib/corner_detector.h"
#include "calib/intrinsics_calibration.h"
#include "calib/synthetic_views.h"
#include "test_support.h"

namespace hd::calib::test {
namespace {

SyntheticCamera small_camera() {
  SyntheticCamera cam;
  cam.size = {320, 240};
  cam.K = cv::Matx33d(300, 0, 165, 0, 302, 118, 0, 0, 1);
  cam.D = (cv::Mat_<double>(1, 5) << -0.2, 0.08, 0.001, -0.0005, 0.0);
  return cam;
}

// Coverage of the 3-sigma intervals the tool reports. If its sigmas are right, each of fx, fy,
// cx, cy misses its truth with p = 0.0027, so over 60 seeds x 4 parameters = 240 checks we expect
// 0.65 misses; P(more than 7 misses | p = 0.0027, n = 240) ~ 1e-7 (binomial tail), so demanding
// >= 97% inside (<= 7 misses) cannot fail by chance, while sigmas too small by a factor of 2
// (p = 0.134, 32 misses expected) fail it for certain.
TEST(Synthetic, ReportedSigmaCoversTheTruth) {
  const SyntheticCamera cam = small_camera();
  const Board board = Board::parse("9x6", 0.02);
#ifdef HD_CALIB_SANITIZED
  // 25 seeds (100 checks, <= 3 misses allowed: P ~ 2e-4 by chance) keep the ASan run short.
  const int seeds = 25, n_views = 12;
#else
  const int seeds = 60, n_views = 12;
#endif
  const double noise_px = 0.3;
  int checks = 0, inside = 0;
  double worst_z = 0;
  for (int seed = 0; seed < seeds; ++seed) {
    std::mt19937 rng(1000 + seed);
    std::normal_distribution<float> noise(0.f, static_cast<float>(noise_px));
    std::vector<View> views;
    for (int v = 0; v < n_views; ++v) {
      auto corners = project_corners(cam, board, random_board_pose(cam, board, rng));
      for (auto& c : corners) {
        const float dy = noise(rng), dx = noise(rng);  // fixed order: see random_board_pose
        c += cv::Point2f(dx, dy);
      }
      views.push_back({"v" + std::to_string(v), corners});
    }
    const auto r = calibrate_intrinsics(views, board, cam.size, DistortionModel{});
    const double truth[4] = {cam.K(0, 0), cam.K(1, 1), cam.K(0, 2), cam.K(1, 2)};
    const double est[4] = {r.fx(), r.fy(), r.cx(), r.cy()};
    for (int i = 0; i < 4; ++i) {
      ASSERT_GT(r.sigma(i), 0.0);
      const double z = std::abs(est[i] - truth[i]) / r.sigma(i);
      worst_z = std::max(worst_z, z);
      ++checks;
      inside += z <= 3.0;
    }
    EXPECT_NEAR(r.rms_px, noise_px * std::sqrt(2.0), 0.1);  // 2-D noise of 0.3 px per axis
  }
  RecordProperty("inside_3sigma", inside);
  RecordProperty("checks", checks);
  EXPECT_GE(inside, checks * 97 / 100) << inside << "/" << checks << " within 3 sigma";
  // And the sigmas are not absurdly large either: the worst miss is a real fraction of 3 sigma.
  EXPECT_GT(worst_z, 1.0);
}

// The whole path on rendered images: renderer -> detector -> subpixel -> calibration.
TEST(Synthetic, RenderedViewsRecoverTheCamera) {
  const SyntheticCamera cam = small_camera();
  const Board board = Board::parse("9x6", 0.02);
  SyntheticRenderer renderer(cam, 3);
  std::mt19937 rng(7);
  std::vector<View> views;
  double sum_sq = 0;
  int n_corners = 0;
  for (int v = 0; v < 12; ++v) {
    const auto pose = random_board_pose(cam, board, rng);
    const cv::Mat img = renderer.render(board, pose, 0.6, 2.0, rng);
    const Detection d = detect_corners(img, board, DetectorOptions{});
    ASSERT_TRUE(d.found()) << "view " << v;
    const auto truth = project_corners(cam, board, pose);
    // The classic detector may number a 9x6 board from either end (a 180 deg relabelling, which
    // calibration does not mind): score the better of the two orders.
    double fwd = 0, rev = 0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const cv::Point2f e = d.corners[i] - truth[i];
      const cv::Point2f f = d.corners[truth.size() - 1 - i] - truth[i];
      fwd += e.dot(e);
      rev += f.dot(f);
    }
    sum_sq += std::min(fwd, rev);
    n_corners += static_cast<int>(truth.size());
    views.push_back({"v" + std::to_string(v), d.corners});
  }
  // Renderer and detector agree to a small fraction of a pixel on where the corners are.
  EXPECT_LT(std::sqrt(sum_sq / n_corners), 0.15);
  const auto r = calibrate_intrinsics(views, board, cam.size, DistortionModel{});
  EXPECT_NEAR(r.fx(), 300.0, 3.0);
  EXPECT_NEAR(r.fy(), 302.0, 3.0);
  EXPECT_NEAR(r.cx(), 165.0, 2.0);
  EXPECT_NEAR(r.cy(), 118.0, 2.0);
  EXPECT_NEAR(r.distortion.at<double>(0, 0), -0.2, 0.03);
}

}  // namespace
}  // namespace hd::calib::test
