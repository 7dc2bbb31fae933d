// `hybrid-calib stereo`: chessboard pairs -> both cameras' p_c and the pose between them, as two
// ordinary calibration files (left camera at the origin).
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>

#include "calib/atomic_file.h"
#include "calib/calibration_file.h"
#include "calib/commands.h"
#include "calib/corner_detector.h"
#include "calib/image_set.h"
#include "calib/intrinsics_calibration.h"
#include "core/opencv_pixels.h"

namespace hd::calib {

namespace {

struct Args {
  std::string images, left_pattern = "left*", right_pattern = "right*", board, out_left, out_right,
                      model = "5";
  double square_m = 0;
  bool force = false;
};

core::Pinhole pinhole_of(const cv::Mat& K, const cv::Mat& D, cv::Size size) {
  core::OpenCvIntrinsics o;
  o.fx = K.at<double>(0, 0);
  o.fy = K.at<double>(1, 1);
  o.cx = K.at<double>(0, 2);
  o.cy = K.at<double>(1, 2);
  o.width = size.width;
  o.height = size.height;
  o.distortion_count = static_cast<int>(std::min<std::size_t>(D.total(), 8));
  for (int i = 0; i < o.distortion_count; ++i)
    o.distortion[static_cast<std::size_t>(i)] = D.at<double>(i);
  return core::from_opencv(o);
}

int run(const Args& a) {
  Board board;
  DistortionModel model;
  try {
    board = Board::parse(a.board, a.square_m);
    model = DistortionModel::parse(a.model);
    check_output_free(a.out_left, a.force);
    check_output_free(a.out_right, a.force);
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  std::vector<NamedImage> left, right;
  try {
    left = load_image_set(a.images, a.left_pattern);
    right = load_image_set(a.images, a.right_pattern);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  if (left.size() != right.size()) {
    std::fprintf(stderr,
                 "error: %s: %zu images match --left-pattern '%s' but %zu match --right-pattern "
                 "'%s'; pairs are taken in name order and need equal counts\n",
                 a.images.c_str(), left.size(), a.left_pattern.c_str(), right.size(),
                 a.right_pattern.c_str());
    return kBadInput;
  }
  const cv::Size size = left.front().gray.size();
  for (const auto& r : right)
    if (r.gray.size() != size) {
      std::fprintf(stderr, "error: %s: image is %dx%d but %s is %dx%d\n", r.name.c_str(),
                   r.gray.cols, r.gray.rows, left.front().name.c_str(), size.width, size.height);
      return kBadInput;
    }
  DetectorOptions opt;
  opt.check_larger = false;
  std::vector<View> lv, rv;
  for (std::size_t i = 0; i < left.size(); ++i) {
    const Detection dl = detect_corners(left[i].gray, board, opt);
    const Detection dr = detect_corners(right[i].gray, board, opt);
    std::printf("[%zu/%zu] %s + %s: %s / %s\n", i + 1, left.size(), left[i].name.c_str(),
                right[i].name.c_str(), dl.describe().c_str(), dr.describe().c_str());
    if (dl.found() && dr.found()) {
      lv.push_back({left[i].name, dl.corners});
      rv.push_back({right[i].name, dr.corners});
    }
  }
  if (lv.size() < 3) {
    std::fprintf(stderr,
                 "error: the board was found in both images of only %zu of %zu pairs; "
                 "need >= 3; nothing written\n",
                 lv.size(), left.size());
    return kFailed;
  }
  // Each camera alone first, then the joint refinement from there: on the shared set this beats
  // OpenCV's stereo_calib flag set (README there: 0.444 vs 0.634 px RMS).
  IntrinsicsResult cl, cr;
  try {
    cl = calibrate_intrinsics(lv, board, size, model);
    cr = calibrate_intrinsics(rv, board, size, model);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: calibration failed: %s\n", e.what());
    return kFailed;
  }
  std::vector<std::vector<cv::Point3f>> obj(lv.size(), board.object_points());
  std::vector<std::vector<cv::Point2f>> pl, pr;
  for (std::size_t i = 0; i < lv.size(); ++i) {
    pl.push_back(lv[i].corners);
    pr.push_back(rv[i].corners);
  }
  cv::Mat K1(cl.camera_matrix), D1 = cl.distortion.clone(), K2(cr.camera_matrix),
                                D2 = cr.distortion.clone(), R, T, E, F;
  const double rms = cv::stereoCalibrate(
      obj, pl, pr, K1, D1, K2, D2, size, R, T, E, F,
      cv::CALIB_USE_INTRINSIC_GUESS | model.cv_flags(),
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 100, 1e-5));
  // The sample's epipolar figure: each undistorted point's distance to the other image's epipolar
  // line, both directions summed, averaged over all points.
  double err_sum = 0;
  std::size_t n_points = 0;
  std::printf("per pair epipolar error (px):");
  for (std::size_t i = 0; i < pl.size(); ++i) {
    std::vector<cv::Point2f> ul, ur;
    cv::undistortPoints(pl[i], ul, K1, D1, cv::noArray(), K1);
    cv::undistortPoints(pr[i], ur, K2, D2, cv::noArray(), K2);
    std::vector<cv::Vec3f> ll, lr;
    cv::computeCorrespondEpilines(ul, 1, F, ll);
    cv::computeCorrespondEpilines(ur, 2, F, lr);
    double e = 0;
    for (std::size_t j = 0; j < ul.size(); ++j)
      e += std::abs(ul[j].x * lr[j][0] + ul[j].y * lr[j][1] + lr[j][2]) +
           std::abs(ur[j].x * ll[j][0] + ur[j].y * ll[j][1] + ll[j][2]);
    err_sum += e;
    n_points += ul.size();
    std::printf(" %s %.3f", lv[i].name.c_str(), e / static_cast<double>(ul.size()));
  }
  const double epipolar = err_sum / static_cast<double>(n_points);
  // Rectified row error: corresponding corners after stereoRectify should share a row.
  cv::Mat R1, R2, P1, P2, Q;
  cv::stereoRectify(K1, D1, K2, D2, size, R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0);
  double row_sq = 0;
  std::size_t row_n = 0;
  for (std::size_t i = 0; i < pl.size(); ++i) {
    std::vector<cv::Point2f> a1, a2;
    cv::undistortPoints(pl[i], a1, K1, D1, R1, P1);
    cv::undistortPoints(pr[i], a2, K2, D2, R2, P2);
    for (std::size_t j = 0; j < a1.size(); ++j) {
      const double dy = a1[j].y - a2[j].y;
      row_sq += dy * dy;
      ++row_n;
    }
  }
  const double row_rms = std::sqrt(row_sq / static_cast<double>(row_n));
  std::printf(
      "\nstereo: %zu pairs, RMS %.4f px, epipolar error %.4f px (OpenCV stereo_calib's "
      "metric), rectified row error RMS %.4f px, baseline %.4f m\n",
      lv.size(), rms, epipolar, row_rms, cv::norm(T));
  // stereoCalibrate's R, T map left-camera points to the right camera: X_r = R X_l + T. The left
  // camera is the world origin, so T_world_right = (R, T)^-1.
  core::Pose T_right_left;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) T_right_left.R(i, j) = R.at<double>(i, j);
    T_right_left.t(i) = T.at<double>(i);
  }
  const core::Pose world_left;  // identity
  const core::Pose world_right = T_right_left.inverse();
  const int pairs = static_cast<int>(lv.size());
  try {
    write_file_atomically(a.out_left,
                          stereo_camera_yaml(pinhole_of(K1, D1, size), world_left, "left", pairs,
                                             rms, epipolar, row_rms),
                          a.force);
    try {
      write_file_atomically(a.out_right,
                            stereo_camera_yaml(pinhole_of(K2, D2, size), world_right, "right",
                                               pairs, rms, epipolar, row_rms),
                            a.force);
    } catch (...) {
      std::error_code ec;
      std::filesystem::remove(a.out_left, ec);  // both files or neither
      throw;
    }
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kWriteError;
  }
  std::printf("wrote %s and %s\n", a.out_left.c_str(), a.out_right.c_str());
  return kOk;
}

}  // namespace

void add_stereo_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("stereo", "both cameras' p_c and the pose between them");
  cmd->add_option("--images", args->images, "folder of chessboard pairs")->required();
  cmd->add_option("--left-pattern", args->left_pattern, "left images, e.g. 'left*'")
      ->capture_default_str();
  cmd->add_option("--right-pattern", args->right_pattern, "right images, e.g. 'right*'")
      ->capture_default_str();
  cmd->add_option("--board", args->board, "inner corners COLSxROWS, e.g. 9x6")->required();
  cmd->add_option("--square", args->square_m, "square size in metres")->required();
  cmd->add_option("--model", args->model, "distortion model: 5 | 8 | rational | fix-k3")
      ->capture_default_str();
  cmd->add_option("--out-left", args->out_left, "left camera's calibration file")->required();
  cmd->add_option("--out-right", args->out_right, "right camera's calibration file")->required();
  cmd->add_flag("--force", args->force, "replace existing outputs (old ones kept as .bak)");
  cmd->footer(
      "Example:\n  hybrid-calib stereo --images data/calib/opencv-left --left-pattern 'left*' "
      "--right-pattern 'right*' --board 9x6 --square 0.025 --out-left L.yml --out-right R.yml");
  cmd->callback([args, &exit_code] { exit_code = run(*args); });
}

}  // namespace hd::calib
