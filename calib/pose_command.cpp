// `hybrid-calib pose`: one view of a board at a known workspace pose -> camera pose P_c.
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <sstream>

#include "calib/atomic_file.h"
#include "calib/board_pose.h"
#include "calib/calibration_file.h"
#include "calib/commands.h"
#include "calib/image_file.h"
#include "calib/image_set.h"

namespace hd::calib {

namespace {

struct Args {
  std::string intrinsics, image, board, board_pose = "0,0,0,0,0,0", expect_dir, out;
  double square_m = 0;
  bool force = false;
};

std::vector<double> parse_numbers(const std::string& s, std::size_t n, const std::string& opt) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument("junk");
    } catch (const std::exception&) {
      throw std::invalid_argument(opt + " '" + s + "': '" + item + "' is not a number");
    }
    if (!std::isfinite(v.back())) throw std::invalid_argument(opt + ": non-finite value");
  }
  if (v.size() != n)
    throw std::invalid_argument(opt + " '" + s + "': expected " + std::to_string(n) +
                                " comma-separated numbers");
  return v;
}

core::Pose pose_from(const std::vector<double>& t, const cv::Vec3d& rvec) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  core::Pose p;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.R(i, j) = R(i, j);
    p.t(i) = t[static_cast<std::size_t>(i)];
  }
  return p;
}

// "x,y,z,rx,ry,rz" (metres; rotation vector in radians) or a YAML file with `t: [x,y,z]` and
// `rvec: [rx,ry,rz]` or `R: [9 numbers, row-major]`: the board-to-world transform T_world_board.
core::Pose parse_board_pose(const std::string& arg) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(arg, ec)) {
    const auto v = parse_numbers(arg, 6, "--board-pose");
    return pose_from({v[0], v[1], v[2]}, cv::Vec3d(v[3], v[4], v[5]));
  }
  try {
    const YAML::Node y = YAML::LoadFile(arg);
    if (!y["t"] || !y["t"].IsSequence() || y["t"].size() != 3)
      throw std::invalid_argument(arg + ": key 't': expected [x, y, z] in metres");
    const auto t = y["t"].as<std::vector<double>>();
    if (y["rvec"]) {
      const auto r = y["rvec"].as<std::vector<double>>();
      if (r.size() != 3) throw std::invalid_argument(arg + ": key 'rvec': expected 3 numbers");
      return pose_from(t, cv::Vec3d(r[0], r[1], r[2]));
    }
    if (y["R"]) {
      const auto r = y["R"].as<std::vector<double>>();
      if (r.size() != 9) throw std::invalid_argument(arg + ": key 'R': expected 9 numbers");
      core::Pose p;
      for (int i = 0; i < 9; ++i) p.R(i / 3, i % 3) = r[static_cast<std::size_t>(i)];
      p.t = {t[0], t[1], t[2]};
      if (!p.valid(1e-4))
        throw std::invalid_argument(arg + ": key 'R': not a rotation (orthonormal, det +1)");
      return p;
    }
    throw std::invalid_argument(arg + ": needs key 'rvec' or 'R'");
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(arg + ": not a board pose YAML file: " + e.what());
  }
}

int run(const Args& a) {
  Board board;
  core::Pose T_world_board;
  PoseOptions opt;
  try {
    board = Board::parse(a.board, a.square_m);
    T_world_board = parse_board_pose(a.board_pose);
    if (!a.expect_dir.empty()) {
      const auto d = parse_numbers(a.expect_dir, 3, "--expect-camera-dir");
      if (std::hypot(d[0], d[1], d[2]) < 1e-9)
        throw std::invalid_argument("--expect-camera-dir: zero vector");
      opt.expect_camera_dir_world = cv::Vec3d(d[0], d[1], d[2]);
    }
    check_output_free(a.out, a.force);
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  CalibrationFile intr;
  try {
    intr = read_calibration_file(a.intrinsics);
  } catch (const CalibrationFileError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  cv::Mat gray;
  try {
    gray = read_gray_image(a.image);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInput;
  }
  if (gray.cols != intr.pinhole.width || gray.rows != intr.pinhole.height) {
    std::fprintf(stderr, "error: %s is %dx%d but %s was calibrated at %dx%d\n", a.image.c_str(),
                 gray.cols, gray.rows, a.intrinsics.c_str(), intr.pinhole.width,
                 intr.pinhole.height);
    return kBadInput;
  }
  PoseResult res;
  try {
    res = estimate_camera_pose(gray, board, intr.pinhole, T_world_board, opt);
  } catch (const PoseRefused& e) {
    std::fprintf(stderr, "error: pose refused: %s\n", e.what());
    return kFailed;
  }
  for (const auto& c : res.candidates)
    std::printf(
        "candidate turn %3d deg: camera at (%.4f, %.4f, %.4f) m, rms %.3f px, origin "
        "square %s (contrast %.0f)\n",
        c.turn_deg, c.camera_pose.t.x(), c.camera_pose.t.y(), c.camera_pose.t.z(), c.rms_px,
        c.colour_ok ? "black" : "white", c.colour_contrast);
  const auto& t = res.camera_pose.t;
  std::printf(
      "camera pose (camera-to-world): centre (%.4f, %.4f, %.4f) m; chosen by %s; "
      "reprojection RMS %.3f px\n",
      t.x(), t.y(), t.z(), res.cue.c_str(), res.rms_px);
  PoseReport rep;
  rep.pinhole = intr.pinhole;
  rep.camera_pose = res.camera_pose;
  rep.reprojection_rms_px = res.rms_px;
  rep.cue = res.cue;
  rep.intrinsics_file = a.intrinsics;
  rep.image_file = a.image;
  rep.board = board;
  rep.board_pose = T_world_board;
  try {
    write_file_atomically(a.out, pose_yaml(rep), a.force);
  } catch (const OutputExists& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kOutputExists;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kWriteError;
  }
  std::printf("wrote %s\n", a.out.c_str());
  return kOk;
}

}  // namespace

void add_pose_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("pose", "estimate P_c (camera-to-world) from a board at a known pose");
  cmd->add_option("--intrinsics", args->intrinsics, "calibration file from `intrinsics`")
      ->required();
  cmd->add_option("--image", args->image, "one image of the board")->required();
  cmd->add_option("--board", args->board, "inner corners COLSxROWS, e.g. 7x7")->required();
  cmd->add_option("--square", args->square_m, "square size in metres")->required();
  cmd->add_option("--board-pose", args->board_pose,
                  "T_world_board: 'x,y,z,rx,ry,rz' (m, rotation vector rad) or a YAML file with "
                  "t and rvec or R")
      ->capture_default_str();
  cmd->add_option("--expect-camera-dir", args->expect_dir,
                  "rough world direction 'X,Y,Z' from the board to the camera; resolves the "
                  "board's 180/90 deg symmetry");
  cmd->add_option("--out", args->out, "output file (intrinsics + camera_pose_R/_t)")->required();
  cmd->add_flag("--force", args->force, "replace an existing output (old one kept as .bak)");
  cmd->footer(
      "Board frame: origin at the inner corner whose diagonal square is black, x along the "
      "first row, y along the first column.\nExample:\n  hybrid-calib pose --intrinsics cam.yml "
      "--image floor.jpg --board 7x7 --square 0.0195 --board-pose 0,0,0,0,0,0 "
      "--expect-camera-dir 0,-1,0 --out cam_pose.yml");
  cmd->callback([args, &exit_code] { exit_code = run(*args); });
}

}  // namespace hd::calib
