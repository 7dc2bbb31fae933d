// `hybrid-calib stereo`: chessboard pairs (files, or two live cameras) -> both cameras' p_c and
// the pose between them, as two ordinary calibration files (left camera at the origin).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <opencv2/calib3d.hpp>

#include "calib/atomic_file.h"
#include "calib/calibration_file.h"
#include "calib/commands.h"
#include "calib/corner_detector.h"
#include "calib/image_set.h"
#include "calib/intrinsics_calibration.h"
#include "calib/live_capture.h"
#include "calib/replay_images.h"
#include "core/opencv_pixels.h"

namespace hd::calib {

namespace {

struct Args {
  std::string images, left_pattern = "left*", right_pattern = "right*", board, out_left, out_right,
                      model = "5";
  std::string left_camera,
      right_camera;  ///< live: camera ids as drivers/camera_factory.h takes them
  double square_m = 0;
  bool force = false;
  int frames = 600;              ///< live: stop after this many pairs looked at
  double duration_s = 120;       ///< live: stop after this long (also the no-frame deadline)
  double timeout_s = 5.0;        ///< per-image detection deadline
  double sync_tolerance_ms = 0;  ///< live: 0 = half the faster camera's frame period
  double min_move = LiveOptions{}.min_move_fraction;  ///< live: of the image diagonal
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

// Each camera alone, then both jointly; prints the figures and writes both files (or neither).
int calibrate_pairs_and_write(const Args& a, const Board& board, const DistortionModel& model,
                              const std::vector<View>& lv, const std::vector<View>& rv,
                              cv::Size size) {
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

// Pairs from a folder: left and right images matched in name order.
int run_files(const Args& a, const Board& board, const DistortionModel& model) {
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
  opt.timeout = std::chrono::milliseconds(static_cast<long>(a.timeout_s * 1000));
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
  return calibrate_pairs_and_write(a, board, model, lv, rv, size);
}

// Pairs from two live cameras; progress goes to the terminal, one line per pair looked at.
int run_live(const Args& a, const Board& board, const DistortionModel& model) {
  if (a.frames <= 0 || !(a.duration_s > 0) || !(a.sync_tolerance_ms >= 0) ||
      !(a.min_move >= 0 && a.min_move < 1)) {
    std::fprintf(stderr,
                 "error: --frames and --duration must be > 0, --sync-tolerance >= 0, --min-move "
                 "in [0, 1)\n");
    return kBadInput;
  }
  const std::string ids[2] = {a.left_camera, a.right_camera};
  const char* options[2] = {"--left-camera", "--right-camera"};
  std::unique_ptr<drivers::CameraSource> cams[2];
  for (int s = 0; s < 2; ++s) {
    try {
      cams[s] = drivers::make_camera_source(ids[s], load_replay_images);
      cams[s]->open();
      cams[s]->start();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: cannot open camera %s (%s): %s\n", ids[s].c_str(), options[s],
                   e.what());
      return kBadInput;  // the sources' destructors stop whatever was started
    }
  }
  LiveOptions opt;
  opt.detector.timeout = std::chrono::milliseconds(static_cast<long>(a.timeout_s * 1000));
  opt.max_duration = std::chrono::milliseconds(static_cast<long>(a.duration_s * 1000));
  opt.sync_tolerance_ns = std::llround(a.sync_tolerance_ms * 1e6);
  opt.min_move_fraction = a.min_move;
  const auto deadline = std::chrono::steady_clock::now() + opt.max_duration;
  int shown = 0;
  char tolerance[64] = "half a frame period";
  if (a.sync_tolerance_ms > 0)
    std::snprintf(tolerance, sizeof tolerance, "%.1f ms", a.sync_tolerance_ms);
  std::printf(
      "live capture from %s (left) and %s (right): need %d varied pairs of the %dx%d board, "
      "frames paired by exposure time within %s\n",
      ids[0].c_str(), ids[1].c_str(), opt.target_views, board.cols, board.rows, tolerance);
  std::fflush(stdout);
  StereoLiveResult res =
      collect_live_pairs(*cams[0], *cams[1], board, opt, [&](const StereoLiveStatus& st) {
        std::printf("%s\n", st.message.c_str());
        std::fflush(stdout);
        return ++shown < a.frames && std::chrono::steady_clock::now() < deadline;
      });
  if (res.stop_reason.empty())
    res.stop_reason = shown >= a.frames ? "--frames " + std::to_string(a.frames) + " reached"
                                        : "--duration reached";
  const uint64_t dropped[2] = {cams[0]->dropped_frames(), cams[1]->dropped_frames()};
  for (auto& c : cams) {
    c->stop();
    c.reset();
  }
  std::printf(
      "examined %d pairs from %s + %s (%d + %d frames; %llu + %llu dropped by the drivers); "
      "kept %zu pairs%s; rejected: %d unsynchronised, %d board in one image only, %d board in "
      "neither, %d too similar, %d malformed frames; stopped: %s\n",
      res.pairs_examined, ids[0].c_str(), ids[1].c_str(), res.frames_left, res.frames_right,
      static_cast<unsigned long long>(dropped[0]), static_cast<unsigned long long>(dropped[1]),
      res.left.size(), res.enough ? ", enough" : "", res.unsynchronised, res.board_in_one_only,
      res.board_in_neither, res.too_similar, res.frames_rejected, res.stop_reason.c_str());
  if (!res.size_mismatch.empty()) {
    std::fprintf(stderr,
                 "error: %s; a stereo calibration needs both cameras at one size; nothing "
                 "written\n",
                 res.size_mismatch.c_str());
    return kBadInput;
  }
  for (int s = 0; s < 2; ++s)
    if ((s == 0 ? res.frames_left : res.frames_right) == 0) {
      std::fprintf(stderr, "error: camera %s (%s) delivered no frame; nothing written\n",
                   ids[s].c_str(), options[s]);
      return kFailed;
    }
  if (res.pairs_examined == 0) {
    std::fprintf(stderr,
                 "error: no synchronised pair in %d + %d frames from cameras %s and %s: %d set "
                 "aside as unsynchronised (exposures farther apart than the tolerance); nothing "
                 "written\n",
                 res.frames_left, res.frames_right, ids[0].c_str(), ids[1].c_str(),
                 res.unsynchronised);
    return kFailed;
  }
  if (res.left.empty()) {
    std::fprintf(stderr,
                 "error: no %dx%d board found in both images of any of the %d pairs from "
                 "cameras %s and %s (in one image only: %d; is --board the number of INNER "
                 "corners, columns x rows?); nothing written\n",
                 board.cols, board.rows, res.pairs_examined, ids[0].c_str(), ids[1].c_str(),
                 res.board_in_one_only);
    return kFailed;
  }
  if (res.left.size() < 3) {
    std::fprintf(stderr,
                 "error: only %zu varied pairs kept from %d pairs of cameras %s and %s; need "
                 ">= 3; nothing written\n",
                 res.left.size(), res.pairs_examined, ids[0].c_str(), ids[1].c_str());
    return kFailed;
  }
  if (!res.enough) std::printf("note: stopped before the pairs were varied enough\n");
  return calibrate_pairs_and_write(a, board, model, res.left, res.right, res.image_size);
}

int run(const Args& a) {
  Board board;
  DistortionModel model;
  try {
    board = Board::parse(a.board, a.square_m);
    model = DistortionModel::parse(a.model);
    if (!(a.timeout_s > 0)) throw std::invalid_argument("--timeout must be > 0 seconds");
    check_output_free(a.out_left, a.force);
    check_output_free(a.out_right, a.force);
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  if (a.images.empty()) {
    const int code = run_live(a, board, model);
    drivers::shutdown_camera_drivers();
    return code;
  }
  return run_files(a, board, model);
}

}  // namespace

void add_stereo_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("stereo", "both cameras' p_c and the pose between them");
  cmd->add_option("--images", args->images, "folder of chessboard pairs");
  cmd->add_option("--left-pattern", args->left_pattern, "left images, e.g. 'left*'")
      ->capture_default_str();
  cmd->add_option("--right-pattern", args->right_pattern, "right images, e.g. 'right*'")
      ->capture_default_str();
  cmd->add_option(
      "--left-camera", args->left_camera,
      "live: left camera, /dev/videoN, mock[:WxH], a GigE id (e.g. Aravis-Fake-SERIAL), "
      "rtp://HOST:PORT or replay:DIR/GLOB[@RATE_HZ[+-OFFSET_MS]] (pictures played as a camera)");
  cmd->add_option("--right-camera", args->right_camera, "live: right camera, ids as above");
  cmd->add_option("--board", args->board, "inner corners COLSxROWS, e.g. 9x6")->required();
  cmd->add_option("--square", args->square_m, "square size in metres")->required();
  cmd->add_option("--model", args->model, "distortion model: 5 | 8 | rational | fix-k3")
      ->capture_default_str();
  cmd->add_option("--out-left", args->out_left, "left camera's calibration file")->required();
  cmd->add_option("--out-right", args->out_right, "right camera's calibration file")->required();
  cmd->add_option("--timeout", args->timeout_s, "per-image detection deadline, seconds")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames,
                  "live: stop after this many pairs looked at (synchronised or not)")
      ->capture_default_str();
  cmd->add_option("--duration", args->duration_s,
                  "live: stop after this many seconds (also how long a silent camera is waited "
                  "for)")
      ->capture_default_str();
  cmd->add_option("--sync-tolerance", args->sync_tolerance_ms,
                  "live: a pair's two exposures may differ by at most this many ms; default "
                  "(0): half the frame period of the faster camera")
      ->capture_default_str();
  cmd->add_option("--min-move", args->min_move,
                  "live: a pair is kept when, against every kept pair, its corners moved this "
                  "fraction of the image diagonal (mean) in at least one image")
      ->capture_default_str();
  cmd->add_flag("--force", args->force, "replace existing outputs (old ones kept as .bak)");
  cmd->footer(
      "Give --images DIR or both --left-camera and --right-camera.\n"
      "Live: frames are paired by exposure time (each frame's capture timestamp on the station's "
      "clock); a pair counts only when its two exposures are within the tolerance (default half "
      "a frame period) and the board is found in both, and is kept when it differs enough from "
      "the pairs kept. It stops when enough varied pairs cover both images, after --frames or "
      "--duration, or when a camera goes silent; then calibrates as for a folder.\n"
      "Examples:\n  hybrid-calib stereo --images data/calib/opencv-left --left-pattern 'left*' "
      "--right-pattern 'right*' --board 9x6 --square 0.025 --out-left L.yml --out-right R.yml\n"
      "  hybrid-calib stereo --left-camera /dev/video0 --right-camera /dev/video2 --board 9x6 "
      "--square 0.025 --out-left L.yml --out-right R.yml");
  cmd->callback([args, &exit_code] {
    // Exactly one source of pairs: a folder, or two cameras.
    const bool files = !args->images.empty(), left = !args->left_camera.empty(),
               right = !args->right_camera.empty();
    std::string problem;
    if (files && (left || right))
      problem = "--images and --left-camera/--right-camera exclude each other";
    else if (!files && !left && !right)
      problem = "no pairs to calibrate";
    else if (left != right)
      problem = left ? "--right-camera is missing" : "--left-camera is missing";
    if (problem.empty()) {
      exit_code = run(*args);
      return;
    }
    std::fprintf(stderr,
                 "error: %s: give either --images DIR (pairs from files) or both --left-camera "
                 "ID and --right-camera ID (live pairs)\n",
                 problem.c_str());
    exit_code = kBadInput;
  });
}

}  // namespace hd::calib
