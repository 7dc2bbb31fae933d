// The tool on real photo sets against OpenCV's published calibration (issue #4 "Done when"),
// driven through the CLI because the CLI is what technicians run.
#include <yaml-cpp/yaml.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "calib/calibration_file.h"
#include "calib/corner_detector.h"
#include "calib/image_set.h"
#include "calib/intrinsics_calibration.h"
#include "calib/intrinsics_uncertainty.h"
#include "calib/larger_board_probe.h"
#include "test_support.h"

namespace hd::calib::test {
namespace {

std::vector<std::string> read_strings(const cv::FileStorage& fs, const std::string& key) {
  std::vector<std::string> v;
  for (const auto& n : fs[key]) v.push_back(static_cast<std::string>(n));
  return v;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// Published figures: shared/data/calib/opencv-left/README.md (OpenCV samples/data
// left_intrinsics.yml, flags = CALIB_FIX_ASPECT_RATIO, 5 coefficients, 13 views).
TEST(RealData, OpencvLeftReproducesPublishedCalibration) {
  ScratchDir tmp;
  const auto out = tmp.path() / "left.yml";
  // The folder also holds the rig's right*.jpg: --pattern keeps the left camera's 13 views.
  const auto r = run_cli("intrinsics --images " + q(data_dir("opencv-left")) +
                         " --pattern 'left*' --board 9x6 --square 0.025 --fix-aspect --out " +
                         q(out) + " --report " + q(tmp.path() / "left.png") + " --ros " +
                         q(tmp.path() / "left_ros.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("[2/13] left02.jpg: board found"), std::string::npos) << r.output;

  const CalibrationFile f = read_calibration_file(out);
  EXPECT_NEAR(f.pinhole.fx, 535.91573, 2.0);
  EXPECT_NEAR(f.pinhole.fy, 535.91573, 2.0);
  // The published figures and the file are OpenCV's numbers; the Pinhole is half a pixel on.
  const cv::Matx33d K_file = file_camera_matrix(out);
  EXPECT_NEAR(K_file(0, 2), 342.28315, 2.0);
  EXPECT_NEAR(K_file(1, 2), 235.57083, 2.0);
  EXPECT_DOUBLE_EQ(f.pinhole.cx, K_file(0, 2) + 0.5);
  EXPECT_DOUBLE_EQ(f.pinhole.cy, K_file(1, 2) + 0.5);
  EXPECT_NEAR(f.avg_reprojection_error_px, 0.39259, 0.05);
  EXPECT_EQ(f.pinhole.width, 640);
  EXPECT_EQ(f.pinhole.height, 480);
  EXPECT_EQ(f.pinhole.distortion_count, 5);
  EXPECT_NEAR(f.pinhole.distortion[0], -0.266373, 0.02);  // k1 is well determined (sigma 0.017)

  cv::FileStorage fs(out.string(), cv::FileStorage::READ);
  EXPECT_EQ(static_cast<int>(fs["nr_of_frames"]), 13);
  EXPECT_EQ(static_cast<int>(fs["flags"]), 2);  // CALIB_FIX_ASPECT_RATIO, as the reference
  EXPECT_EQ(static_cast<std::string>(fs["worst_view"]), "left02.jpg");
  cv::Mat per_view;
  fs["per_view_reprojection_errors"] >> per_view;
  ASSERT_EQ(per_view.total(), 13u);
  EXPECT_NEAR(per_view.at<double>(1), 1.18, 0.1);  // reference: left02 1.18 px
  EXPECT_TRUE(contains(read_strings(fs, "outlier_views"), "left02.jpg"));
  // This set is a reasonable one: the principal point must NOT be flagged (the control for the
  // webcam test below), while k3 (sigma 0.29 in the README) must be.
  const auto codes = read_strings(fs, "warning_codes");
  EXPECT_FALSE(contains(codes, "principal_point")) << r.output;
  EXPECT_TRUE(contains(codes, "distortion")) << r.output;
  cv::Mat sd;
  fs["intrinsics_std_dev"] >> sd;
  ASSERT_GE(sd.total(), 4u);
  EXPECT_NEAR(sd.at<double>(2), 1.42, 0.5);  // README: sigma cx 1.42 px (flags 0)

  // ROS camera_info carries the same numbers.
  const YAML::Node ros = YAML::LoadFile((tmp.path() / "left_ros.yaml").string());
  EXPECT_EQ(ros["distortion_model"].as<std::string>(), "plumb_bob");
  const auto K = ros["camera_matrix"]["data"].as<std::vector<double>>();
  ASSERT_EQ(K.size(), 9u);
  EXPECT_NEAR(K[0], f.pinhole.fx, 1e-6);
  EXPECT_NEAR(K[2], file_camera_matrix(out)(0, 2), 1e-6);  // both OpenCV's convention
  EXPECT_TRUE(fs::file_size(tmp.path() / "left.png") > 10000);
}

// The cheap larger-board probe on real photos of a board known to be 9x6 (OpenCV's left*.jpg,
// whose outer squares are cut by the board's edge): with --board 9x6 no view's checker goes on
// past an edge, with --board 8x6 (a part of the board) every view where the pattern is found
// has one more column beyond an edge.
TEST(RealData, LargerBoardProbeSeesTheRestOfTheBoardAndOnlyThat) {
  const auto images = load_image_set(data_dir("opencv-left"), "left*");
  ASSERT_EQ(images.size(), 13u);
  DetectorOptions opt;
  opt.check_larger = false;
  opt.use_sb_fallback = false;
  int found9 = 0, found8 = 0;
  for (const auto& im : images) {
    const Board b9 = Board::parse("9x6", 0.025), b8 = Board::parse("8x6", 0.025);
    const Detection d9 = detect_corners(im.gray, b9, opt);
    ASSERT_TRUE(d9.found()) << im.name;
    ++found9;
    const LargerBoardProbe p9 = probe_beyond_edges(im.gray, b9, d9.corners);
    EXPECT_FALSE(p9.continues) << im.name << " 9x6";
    EXPECT_GE(p9.sides_sampled, 3) << im.name;
    const Detection d8 = detect_corners(im.gray, b8, opt);
    if (!d8.found()) continue;
    ++found8;
    EXPECT_TRUE(probe_beyond_edges(im.gray, b8, d8.corners).continues) << im.name << " 8x6";
  }
  EXPECT_EQ(found9, 13);
  EXPECT_GE(found8, 8);  // the classic detector finds an 8x6 part in 11 of the 13 here
}

// The parameters' sigma through the Schur complement (calib/intrinsics_uncertainty.h) against
// calibrateCameraExtended's own, which inverts the whole normal matrix, on the 13 shared views,
// for each distortion model with and without a fixed aspect ratio.
TEST(RealData, SigmaMatchesCalibrateCameraExtended) {
  const Board board = Board::parse("9x6", 0.025);
  std::vector<View> views;
  cv::Size size;
  for (const auto& im : load_image_set(data_dir("opencv-left"), "left*")) {
    const Detection d = detect_corners(im.gray, board, DetectorOptions{});
    ASSERT_TRUE(d.found()) << im.name;
    views.push_back({im.name, d.corners});
    size = im.gray.size();
  }
  for (const char* name : {"5", "fix-k3", "rational"})
    for (const bool fix_aspect : {false, true}) {
      DistortionModel model = DistortionModel::parse(name);
      model.fix_aspect = fix_aspect;
      const IntrinsicsResult r = calibrate_intrinsics(views, board, size, model, nullptr, false);
      EXPECT_TRUE(r.std_dev_intrinsics.empty());
      const cv::Mat ours = intrinsics_std_dev(views, board, r);
      // The peer: the same calibration through the Extended overload.
      std::vector<std::vector<cv::Point3f>> obj(views.size(), board.object_points());
      std::vector<std::vector<cv::Point2f>> img;
      for (const auto& v : views) img.push_back(v.corners);
      cv::Mat K = cv::Mat::eye(3, 3, CV_64F), D, sd, sde, pve;
      std::vector<cv::Mat> rv, tv;
      cv::calibrateCamera(
          obj, img, size, K, D, rv, tv, sd, sde, pve, model.cv_flags() | cv::CALIB_USE_LU,
          cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, DBL_EPSILON));
      EXPECT_NEAR(K.at<double>(0, 0), r.fx(), 1e-9 * r.fx());
      const int n = ours.cols;
      for (int i = 0; i < n; ++i) {
        const double peer = sd.at<double>(i);
        if (i == 0 && fix_aspect) {  // OpenCV reports 0; fx = fy's sigma here
          EXPECT_EQ(peer, 0.0);
          EXPECT_EQ(ours.at<double>(0, 0), ours.at<double>(0, 1));
          continue;
        }
        EXPECT_NEAR(ours.at<double>(0, i), peer, 1e-4 * peer + 1e-12)
            << name << (fix_aspect ? " fix-aspect" : "") << " parameter " << i;
      }
    }
}

TEST(RealData, WebcamUsesAllViewsWarnsPrincipalPointAndGivesAPose) {
  ScratchDir tmp;
  const auto dir = data_dir("webcam-7x7");
  const auto out = tmp.path() / "web.yml";
  const auto r = run_cli("intrinsics --images " + q(dir) +
                         " --pattern 'left*' --board 7x7 --square 0.0195 --out " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  cv::FileStorage fs(out.string(), cv::FileStorage::READ);
  EXPECT_EQ(static_cast<int>(fs["nr_of_frames"]), 19);
  const auto codes = read_strings(fs, "warning_codes");
  EXPECT_TRUE(contains(codes, "principal_point")) << r.output;
  EXPECT_NE(r.output.find("WARNING [principal_point]"), std::string::npos);
  // README's own run (flags 0): fx 878.48, cx 197.76, cy 217.89, RMS 0.5736.
  const CalibrationFile f = read_calibration_file(out);
  EXPECT_NEAR(f.pinhole.fx, 878.48, 2.0);
  EXPECT_NEAR(file_camera_matrix(out)(0, 2), 197.76, 2.0);
  EXPECT_NEAR(file_camera_matrix(out)(1, 2), 217.89, 2.0);
  EXPECT_NEAR(f.avg_reprojection_error_px, 0.5736, 0.05);
  double hull = fs["coverage_hull_fraction"];
  EXPECT_NEAR(hull, 0.44, 0.05);  // README: the corners' hull covers 44% of the image

  // Pose from the board on the floor. A 7x7 board is 180 deg symmetric even in colour: without a
  // cue the tool must refuse, and write nothing.
  const auto img = dir / "perspectiveimg.jpg";
  const auto pose_out = tmp.path() / "pose.yml";
  const std::string base = "pose --intrinsics " + q(out) + " --image " + q(img) +
                           " --board 7x7 --square 0.0195 --board-pose 1,2,0,0,0,0 --out " +
                           q(pose_out);
  const auto refused = run_cli(base);
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.output.find("refused"), std::string::npos) << refused.output;
  EXPECT_FALSE(fs::exists(pose_out));

  const auto a = run_cli(base + " --expect-camera-dir 0,1,-1");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const CalibrationFile pa = read_calibration_file(pose_out);
  ASSERT_TRUE(pa.camera_pose.has_value());
  cv::FileStorage pfs(pose_out.string(), cv::FileStorage::READ);
  const double rms = pfs["pose_reprojection_error"];
  EXPECT_LT(rms, 1.5);
  EXPECT_GT(rms, 0.0);

  // Independent check of the convention X_world = R X_cam + t: project the board's world corners
  // through the written pose + pinhole + distortion and compare with OpenCV's detector.
  const cv::Mat gray = cv::imread(img.string(), cv::IMREAD_GRAYSCALE);
  const Board board = Board::parse("7x7", 0.0195);
  const Detection found = detect_corners(gray, board, DetectorOptions{});
  ASSERT_TRUE(found.found());
  const std::vector<cv::Point2f>& det = found.corners;
  const auto& P = *pa.camera_pose;
  std::vector<cv::Point3f> cam_pts;
  for (const auto& o : board.object_points()) {
    const Eigen::Vector3d w(o.x + 1.0, o.y + 2.0, o.z);  // board pose: translation (1, 2, 0)
    const Eigen::Vector3d c = P.to_camera(w);
    ASSERT_GT(c.z(), 0.0);
    cam_pts.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()),
                         static_cast<float>(c.z()));
  }
  std::vector<cv::Point2f> proj;
  // OpenCV's K as the file holds it (not the Pinhole, which is half a pixel on).
  const cv::Mat K(file_camera_matrix(pose_out));
  cv::Mat D(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) D.at<double>(i) = pa.pinhole.distortion[static_cast<std::size_t>(i)];
  cv::projectPoints(cam_pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D, proj);
  // The detector's numbering may start at either symmetric corner: compare as point sets.
  double worst = 0, sum = 0;
  for (const auto& p : proj) {
    double best = 1e9;
    for (const auto& d : det) best = std::min(best, static_cast<double>(cv::norm(p - d)));
    worst = std::max(worst, best);
    sum += best * best;
  }
  // The file's figure is what this independent projection gives; the worst corner (bottom edge,
  // where the webcam set's distortion is extrapolated) stays within a few pixels.
  EXPECT_NEAR(std::sqrt(sum / static_cast<double>(proj.size())), rms, 0.01);
  EXPECT_LT(worst, 4.0);

  // The opposite prior picks the other 180 deg candidate: the camera centres are mirror images
  // through the board centre's normal (same height, reflected x/y about the centre).
  const auto b = run_cli(base + " --expect-camera-dir 0,-1,-1 --force");
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_TRUE(fs::exists(pose_out.string() + ".bak"));
  const CalibrationFile pb = read_calibration_file(pose_out);
  const Eigen::Vector3d centre(1.0 + 3 * 0.0195, 2.0 + 3 * 0.0195, 0.0);
  const Eigen::Vector3d ca = pa.camera_pose->t - centre, cb = pb.camera_pose->t - centre;
  EXPECT_NEAR(ca.z(), cb.z(), 1e-3);
  EXPECT_NEAR(ca.x(), -cb.x(), 2e-3);
  EXPECT_NEAR(ca.y(), -cb.y(), 2e-3);
  EXPECT_GT(ca.y(), 0.0);  // the prior (0, 1, -1) chose the candidate on the +y side
}

}  // namespace
}  // namespace hd::calib::test

namespace hd::calib::test {
namespace {

double figure_after(const std::string& out, const std::string& key) {
  const auto p = out.find(key);
  if (p == std::string::npos) return 1e9;
  return std::stod(out.substr(p + key.size()));
}

// Issue 13 item 1. README of opencv-left: OpenCV's stereo_calib sample gets RMS 0.634 px and an
// epipolar error of 0.445 px on these 13 pairs; calibrating each camera first then refining
// jointly gives 0.444 / 0.262 px, T = 3.343 squares, rectified rows 0.22-0.30 px apart.
TEST(RealData, StereoOnTheSharedPairsBeatsOpenCvsSample) {
  ScratchDir tmp;
  const auto L = tmp.path() / "L.yml", R = tmp.path() / "R.yml";
  const auto r = run_cli("stereo --images " + q(data_dir("opencv-left")) +
                         " --left-pattern 'left*' --right-pattern 'right*' --board 9x6 "
                         "--square 0.025 --out-left " +
                         q(L) + " --out-right " + q(R));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double rms = figure_after(r.output, "pairs, RMS "),
               epi = figure_after(r.output, "px, epipolar error "),
               row = figure_after(r.output, "row error RMS ");
  EXPECT_LE(rms, 0.634) << r.output;
  EXPECT_LE(epi, 0.445) << r.output;
  EXPECT_NEAR(rms, 0.444, 0.02);
  EXPECT_NEAR(epi, 0.262, 0.02);
  EXPECT_GT(row, 0.1);
  EXPECT_LT(row, 0.35);
  EXPECT_NE(r.output.find("per pair epipolar error (px): left01.jpg"), std::string::npos);
  const CalibrationFile fl = read_calibration_file(L), fr = read_calibration_file(R);
  ASSERT_TRUE(fl.camera_pose && fr.camera_pose);
  EXPECT_NEAR(fl.camera_pose->t.norm(), 0.0, 1e-12);  // the left camera is the origin
  EXPECT_NEAR(fr.camera_pose->t.norm(), 3.343 * 0.025, 0.002);
  EXPECT_EQ(fr.pinhole.width, 640);
  // The files hold OpenCV's numbers, the Pinhole is half a pixel on (one conversion).
  EXPECT_DOUBLE_EQ(fl.pinhole.cx, file_camera_matrix(L)(0, 2) + 0.5);
}

TEST(RealData, StereoRefusesUnpairedSetsNamingTheFolder) {
  ScratchDir in, out;
  const auto src = data_dir("opencv-left");
  for (const char* f : {"left01.jpg", "left02.jpg", "left03.jpg", "right01.jpg", "right02.jpg"})
    fs::copy_file(src / f, in.path() / f);
  const auto r =
      run_cli("stereo --images " + q(in.path()) + " --board 9x6 --square 0.025 --out-left " +
              q(out.path() / "L.yml") + " --out-right " + q(out.path() / "R.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(in.path().string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("3 images match --left-pattern"), std::string::npos) << r.output;
  EXPECT_TRUE(out.listing().empty());
}

}  // namespace
}  // namespace hd::calib::test
