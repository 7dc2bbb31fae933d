// `hybrid-calib intrinsics`: folder (or live camera) -> calibration file, report, warnings.
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "calib/atomic_file.h"
#include "calib/calibration_file.h"
#include "calib/commands.h"
#include "calib/corner_detector.h"
#include "calib/image_file.h"
#include "calib/image_set.h"
#include "calib/intrinsics_assessment.h"
#include "calib/larger_board_probe.h"
#include "calib/live_capture.h"
#include "calib/replay_images.h"
#include "calib/report_image.h"

namespace hd::calib {

namespace {

struct Args {
  std::string images, pattern = "*", camera, board = "", out, report, ros, model = "5";
  double square_m = 0;
  bool fix_aspect = false, force = false, cross_validate = false;
  double timeout_s = 5.0;
  int frames = 600;         ///< live: stop after examining this many frames
  double duration_s = 120;  ///< live: stop after this long (also the no-frame deadline)
};

void print_summary(const IntrinsicsReport& rep) {
  const auto& r = rep.result;
  std::printf("calibrated %zu views, model %s, image %dx%d\n", r.views.size(),
              rep.model_name.c_str(), r.image_size.width, r.image_size.height);
  std::printf("  RMS %.4f px\n", r.rms_px);
  std::printf("  fx %.3f +- %.3f  fy %.3f +- %.3f\n", r.fx(), r.sigma(0), r.fy(), r.sigma(1));
  std::printf("  cx %.3f +- %.3f  cy %.3f +- %.3f\n", r.cx(), r.sigma(2), r.cy(), r.sigma(3));
  std::printf("  distortion");
  for (int i = 0; i < r.distortion.cols; ++i)
    std::printf(" %.5g+-%.2g", r.distortion.at<double>(0, i), r.sigma(4 + i));
  std::printf("\n  per view:");
  for (const auto& v : r.views)
    std::printf(" %s %.3f%s", v.name.c_str(), v.rms_px, v.outlier ? " (OUTLIER)" : "");
  const auto& worst = r.views[static_cast<std::size_t>(r.worst_view)];
  std::printf("\n  worst view: %s (%.3f px)\n", worst.name.c_str(), worst.rms_px);
  if (!rep.cross_validation.computed)
    std::printf("  cross-validation: not computed (--cross-validate, needs >= 6 views)\n");
  if (rep.cross_validation.computed)
    std::printf(
        "  cross-validation (%d vs %d views): inside the covered area max %.3f px, RMS "
        "%.3f px; whole image max %.3f px, RMS %.3f px\n",
        rep.cross_validation.views_a, rep.cross_validation.views_b,
        rep.cross_validation.covered_max_px, rep.cross_validation.covered_rms_px,
        rep.cross_validation.max_px, rep.cross_validation.rms_px);
  const auto& c = rep.coverage;
  std::printf(
      "  coverage: hull %.0f%% of the image, %.0f%% of 8x6 cells, board size %.0f-%.0f%%, "
      "tilt %.0f-%.0f deg\n",
      100 * c.hull_fraction, 100 * c.grid_fraction, 100 * c.board_size_min, 100 * c.board_size_max,
      c.tilt_min_deg, c.tilt_max_deg);
  for (const auto& w : rep.warnings)
    std::printf("WARNING [%s] %s\n", w.code.c_str(), w.message.c_str());
  const IntrinsicsCpu& t = rep.cpu;
  // The core is what OpenCV's calibration sample does too; the rest are this tool's extras.
  std::printf("  cpu, core: images + detection + cornerSubPix %.3f s, calibration %.3f s\n",
              t.detection_s - t.larger_check_s, t.calibration_s);
  std::printf(
      "  cpu, quality figures: larger-board check %.4f s (edge probe %.4f s, SB confirmation "
      "%.4f s on %d views), sigma %.4f s, cross-validation %.3f s%s, coverage + warnings %.4f "
      "s\n",
      t.larger_check_s, t.larger_probe_s, t.larger_confirm_s, t.larger_confirmations, t.sigma_s,
      t.cross_validation_s, rep.cross_validation.computed ? "" : " (not run)", t.coverage_s);
  std::printf("  cpu, process so far %.3f s (start-up before the images %.3f s)\n", process_cpu_s(),
              t.startup_s);
}

int calibrate_and_write(const Args& a, const Board& board, const DistortionModel& model,
                        const std::vector<View>& views, cv::Size image_size,
                        const cv::Mat& background, const std::vector<Warning>& input_warnings = {},
                        const IntrinsicsCpu& detection_cpu = {});

// Live views from --camera; progress goes to the terminal, one line per examined frame.
int run_live(const Args& a, const Board& board, const DistortionModel& model) {
  if (a.frames <= 0 || !(a.duration_s > 0)) {
    std::fprintf(stderr, "error: --frames and --duration must be > 0\n");
    return kBadInput;
  }
  std::unique_ptr<drivers::CameraSource> cam;
  try {
    cam = drivers::make_camera_source(a.camera, load_replay_images);
    cam->open();
    cam->start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: cannot open camera %s: %s\n", a.camera.c_str(), e.what());
    return kBadInput;
  }
  LiveOptions opt;
  opt.detector.timeout = std::chrono::milliseconds(static_cast<long>(a.timeout_s * 1000));
  opt.max_duration = std::chrono::milliseconds(static_cast<long>(a.duration_s * 1000));
  const auto deadline = std::chrono::steady_clock::now() + opt.max_duration;
  cv::Mat background;
  int shown = 0;
  std::printf("live capture from %s: need %d varied views of the %dx%d board\n", a.camera.c_str(),
              opt.target_views, board.cols, board.rows);
  std::fflush(stdout);
  const LiveResult res = collect_live_views(*cam, board, opt, [&](const LiveStatus& st) {
    std::printf("%s\n", st.message.c_str());
    std::fflush(stdout);
    if (background.empty() && st.gray && st.corners && !st.corners->empty())
      background = st.gray->clone();
    return ++shown < a.frames && std::chrono::steady_clock::now() < deadline;
  });
  const uint64_t dropped = cam->dropped_frames();
  cam->stop();
  cam.reset();
  std::printf(
      "examined %d frames from %s (%d rejected, %llu dropped by the driver), kept %zu "
      "views%s\n",
      res.frames_examined, a.camera.c_str(), res.frames_rejected,
      static_cast<unsigned long long>(dropped), res.views.size(), res.enough ? ", enough" : "");
  if (res.frames_examined == 0) {
    std::fprintf(stderr, "error: camera %s delivered no frame within %.1f s; nothing written\n",
                 a.camera.c_str(), a.duration_s);
    return kFailed;
  }
  if (res.views.empty()) {
    std::fprintf(stderr,
                 "error: no %dx%d board found in any of the %d frames from camera %s (is "
                 "--board the number of INNER corners, columns x rows?); nothing written\n",
                 board.cols, board.rows, res.frames_examined, a.camera.c_str());
    return kFailed;
  }
  if (res.views.size() < 3) {
    std::fprintf(stderr,
                 "error: only %zu varied views kept from %d frames of camera %s; need >= 3; "
                 "nothing written\n",
                 res.views.size(), res.frames_examined, a.camera.c_str());
    return kFailed;
  }
  if (!res.enough)
    std::printf("note: stopped before the views were varied enough; see the warnings\n");
  return calibrate_and_write(a, board, model, res.views, res.image_size, background);
}

int run(const Args& a) {
  Board board;
  DistortionModel model;
  try {
    board = Board::parse(a.board, a.square_m);
    model = DistortionModel::parse(a.model);
    if (a.fix_aspect) model.fix_aspect = true;
    if (!(a.timeout_s > 0)) throw std::invalid_argument("--timeout must be > 0 seconds");
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  try {
    check_output_free(a.out, a.force);
    if (!a.report.empty()) check_output_free(a.report, a.force);
    if (!a.ros.empty()) check_output_free(a.ros, a.force);
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  }
  if (!a.camera.empty()) {
    const int code = run_live(a, board, model);
    drivers::shutdown_camera_drivers();
    return code;
  }
  const double cpu_start = process_cpu_s();
  std::vector<NamedImage> images;
  try {
    images = load_image_set(a.images, a.pattern);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  DetectorOptions det_opt;
  det_opt.timeout = std::chrono::milliseconds(static_cast<long>(a.timeout_s * 1000));
  // The larger-board check runs on every view, in two stages: a probe of the squares beyond
  // the pattern's edges (microseconds), and only where the checker goes on there,
  // findChessboardCornersSB with CALIB_CB_LARGER to confirm it (tens of ms, and fooled by steep
  // views of a board with a white margin).
  det_opt.check_larger = false;
  std::vector<View> views;
  std::vector<std::size_t> larger_idx;  ///< views (index into views) inside a larger board
  std::vector<int> larger_count;
  IntrinsicsCpu cpu;
  cpu.startup_s = cpu_start;  // the loader, the libraries' initialisers, option parsing
  cv::Mat background;
  const std::size_t n = images.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Detection d = detect_corners(images[i].gray, board, det_opt);
    std::string larger_note;
    if (d.found()) {
      const double c0 = process_cpu_s();
      const LargerBoardProbe probe = probe_beyond_edges(images[i].gray, board, d.corners);
      const double c1 = process_cpu_s();
      cpu.larger_probe_s += c1 - c0;
      if (probe.continues) {
        ++cpu.larger_confirmations;
        const int c = larger_board_corners(images[i].gray, board);
        cpu.larger_confirm_s += process_cpu_s() - c1;
        larger_note = c > 0 ? ", checker continues past an edge: SB sees a larger board of " +
                                  std::to_string(c) + " inner corners"
                            : ", checker continues past an edge: SB sees no larger board";
        if (c > 0) {
          larger_idx.push_back(views.size());
          larger_count.push_back(c);
        }
      }
      views.push_back({images[i].name, d.corners});
      if (background.empty()) background = images[i].gray;
    }
    std::printf("[%zu/%zu] %s: %s (%.0f ms)%s\n", i + 1, n, images[i].name.c_str(),
                d.describe().c_str(), 1000 * d.seconds, larger_note.c_str());
    std::fflush(stdout);
  }
  cpu.larger_check_s = cpu.larger_probe_s + cpu.larger_confirm_s;
  cpu.detection_s = process_cpu_s() - cpu_start;
  std::vector<std::string> larger;
  for (auto v : larger_idx) larger.push_back(views[v].name);
  // A larger board is the views' verdict, not one view's: when at least half of the views that
  // showed the pattern see it inside a larger board, --board is wrong and nothing is written; a
  // minority of such views (SB at a steep angle, a second board in the background) is dropped,
  // by name, and the rest calibrate.
  std::vector<Warning> input_warnings;
  if (!larger.empty() && 2 * larger.size() < views.size()) {
    for (std::size_t k = 0; k < larger.size(); ++k)
      input_warnings.push_back(
          {"larger_board_view",
           larger[k] + ": the " + std::to_string(board.cols) + "x" + std::to_string(board.rows) +
               " pattern looked part of a larger board (" + std::to_string(larger_count[k]) +
               " inner corners) while " + std::to_string(views.size() - larger.size()) +
               " other views see a board of that size: view dropped"});
    for (auto it = larger_idx.rbegin(); it != larger_idx.rend(); ++it)
      views.erase(views.begin() + static_cast<std::ptrdiff_t>(*it));
    for (const auto& w : input_warnings)
      std::printf("WARNING [%s] %s\n", w.code.c_str(), w.message.c_str());
    larger.clear();
  }
  if (!larger.empty()) {
    std::fprintf(stderr,
                 "error: in %s (and %zu more) the %dx%d pattern is part of a larger chessboard: "
                 "--board must give ALL inner corners, columns x rows; nothing written\n",
                 larger.front().c_str(), larger.size() - 1, board.cols, board.rows);
    return kBadInput;
  }
  if (views.empty()) {
    std::fprintf(stderr,
                 "error: no %dx%d board found in any of the %zu images in %s (is --board the "
                 "number of INNER corners, columns x rows?)\n",
                 board.cols, board.rows, n, a.images.c_str());
    return kFailed;
  }
  if (views.size() < 3) {
    std::fprintf(stderr, "error: the board was found in only %zu of %zu images in %s; need >= 3\n",
                 views.size(), n, a.images.c_str());
    return kFailed;
  }
  return calibrate_and_write(a, board, model, views, images.front().gray.size(), background,
                             input_warnings, cpu);
}

int calibrate_and_write(const Args& a, const Board& board, const DistortionModel& model,
                        const std::vector<View>& views, cv::Size image_size,
                        const cv::Mat& background, const std::vector<Warning>& input_warnings,
                        const IntrinsicsCpu& detection_cpu) {
  IntrinsicsReport rep;
  try {
    rep = assess_intrinsics(views, board, image_size, model, a.cross_validate);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: calibration failed: %s\n", e.what());
    return kFailed;
  }
  rep.warnings.insert(rep.warnings.begin(), input_warnings.begin(), input_warnings.end());
  rep.cpu.detection_s = detection_cpu.detection_s;
  rep.cpu.larger_check_s = detection_cpu.larger_check_s;
  rep.cpu.startup_s = detection_cpu.startup_s;
  rep.cpu.larger_probe_s = detection_cpu.larger_probe_s;
  rep.cpu.larger_confirm_s = detection_cpu.larger_confirm_s;
  rep.cpu.larger_confirmations = detection_cpu.larger_confirmations;
  print_summary(rep);
  try {
    write_file_atomically(a.out, intrinsics_yaml(rep), a.force);
    std::printf("wrote %s\n", a.out.c_str());
    if (!a.ros.empty()) {
      write_file_atomically(a.ros, ros_camera_info_yaml(rep.result, "camera"), a.force);
      std::printf("wrote %s (ROS camera_info)\n", a.ros.c_str());
    }
    if (!a.report.empty()) {
      write_file_atomically(a.report,
                            encode_png(render_report(background, views, rep.result, rep.coverage)),
                            a.force);
      std::printf("wrote %s (report picture)\n", a.report.c_str());
    }
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kWriteError;
  }
  return kOk;
}

}  // namespace

void add_intrinsics_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("intrinsics", "estimate p_c (pinhole + distortion) from views");
  auto* src = cmd->add_option("--images", args->images,
                              "folder of chessboard images (.jpg .png .bmp .tif .pgm .ppm)");
  cmd->add_option("--pattern", args->pattern, "only files whose name matches, e.g. 'left*'")
      ->capture_default_str();
  auto* cam = cmd->add_option("--camera", args->camera,
                              "live camera: /dev/videoN, mock[:WxH], a GigE id "
                              "(e.g. Aravis-Fake-SERIAL), rtp://HOST:PORT or "
                              "replay:DIR/GLOB[@RATE_HZ] (pictures played as a camera)");
  src->excludes(cam);
  cmd->add_option("--board", args->board, "inner corners COLSxROWS, e.g. 9x6")->required();
  cmd->add_option("--square", args->square_m, "square size in metres, e.g. 0.025")->required();
  cmd->add_option("--out", args->out, "calibration file (OpenCV FileStorage YAML)")->required();
  cmd->add_option("--model", args->model,
                  "distortion model: 5 | 8 | rational | fix-k3 | fix-aspect")
      ->capture_default_str();
  cmd->add_flag("--fix-aspect", args->fix_aspect, "fix fx/fy = 1 (CALIB_FIX_ASPECT_RATIO)");
  cmd->add_flag("--cross-validate", args->cross_validate,
                "also calibrate the even and the odd views alone and compare (two more "
                "calibrations; off by default to keep the run as cheap as OpenCV's sample)");
  cmd->add_option("--report", args->report, "report picture (PNG)");
  cmd->add_option("--ros", args->ros, "also write ROS camera_info YAML");
  cmd->add_option("--timeout", args->timeout_s, "per-image detection deadline, seconds")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "live: stop after examining this many frames")
      ->capture_default_str();
  cmd->add_option("--duration", args->duration_s, "live: stop after this many seconds")
      ->capture_default_str();
  cmd->add_flag("--force", args->force, "replace existing outputs (old ones kept as .bak)");
  cmd->footer(
      "Prints the CPU time of the core (images, detection, calibration) and of each extra "
      "quality figure (larger-board check, sigma, cross-validation, coverage) apart.\n"
      "Example:\n  hybrid-calib intrinsics --images data/calib/opencv-left --board 9x6 "
      "--square 0.025 --pattern 'left*' --fix-aspect --out left.yml --report left.png");
  cmd->callback([args, cmd, &exit_code] {
    if (args->images.empty() && args->camera.empty()) {
      std::fprintf(stderr, "error: give --images DIR or --camera ID\n");
      exit_code = kBadInput;
      return;
    }
    exit_code = run(*args);
    (void)cmd;
  });
}

}  // namespace hd::calib
