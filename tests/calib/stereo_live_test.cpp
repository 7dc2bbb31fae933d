// hybrid-calib stereo from two live cameras, end to end through the program: real photo pairs
// replayed as two cameras must give the files path's figures, a rendered rig must give its known
// baseline, and unopenable cameras, different sizes, unsynchronised streams and pairs without
// the board in both images are counted, named and refused. Every wait is for the program's exit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/calib3d.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "calib/board.h"
#include "calib/calibration_file.h"
#include "calib/image_file.h"
#include "calib/replay_images.h"
#include "calib/synthetic_views.h"
#include "core/opencv_pixels.h"
#include "test_support.h"

namespace hd::calib::test {
namespace {

const std::string kBoardArgs = "--board 9x6 --square 0.025";

struct StereoFigures {
  int pairs = 0;
  double rms_px = -1, epipolar_px = -1, baseline_m = -1;
};

// From the summary line "stereo: 13 pairs, RMS 0.4448 px, epipolar error 0.2621 px (...),
// rectified row error RMS 0.2605 px, baseline 0.0835 m". (No std::regex: GCC 12 warns inside it
// under the sanitizers, and warnings are errors.)
StereoFigures figures(const std::string& output) {
  StereoFigures f;
  const auto at = output.find("\nstereo: ");
  if (at == std::string::npos) return f;
  const std::string line = output.substr(at + 1, output.find('\n', at + 1) - at - 1);
  const auto b = line.find("baseline ");
  if (std::sscanf(line.c_str(), "stereo: %d pairs, RMS %lf px, epipolar error %lf px", &f.pairs,
                  &f.rms_px, &f.epipolar_px) != 3 ||
      b == std::string::npos || std::sscanf(line.c_str() + b, "baseline %lf m", &f.baseline_m) != 1)
    return StereoFigures{};
  return f;
}

// The whole output line that starts with `start` ("" if none).
std::string line_starting(const std::string& output, const std::string& start) {
  const auto at = output.find(start);
  if (at == std::string::npos || (at > 0 && output[at - 1] != '\n')) return "";
  return output.substr(at, output.find('\n', at) - at);
}

std::string replay(const fs::path& folder, const std::string& glob, const std::string& rate = "") {
  return "replay:" + (folder / glob).string() + rate;
}

TEST(CameraFactory, ReplayIdsNameFolderPatternRateAndOffset) {
  EXPECT_EQ(drivers::camera_kind("replay:data/left*.jpg"), drivers::CameraKind::kReplay);
  const drivers::ReplayId a = drivers::parse_replay_id("replay:data/left*.jpg@30+20");
  EXPECT_EQ(a.folder, "data");
  EXPECT_EQ(a.pattern, "left*.jpg");
  EXPECT_DOUBLE_EQ(a.rate_hz, 30.0);
  EXPECT_DOUBLE_EQ(a.offset_ms, 20.0);
  const drivers::ReplayId b = drivers::parse_replay_id("replay:right*.png@7.5-12.5");
  EXPECT_EQ(b.folder, ".");
  EXPECT_DOUBLE_EQ(b.rate_hz, 7.5);
  EXPECT_DOUBLE_EQ(b.offset_ms, -12.5);
  const drivers::ReplayId c =
      drivers::parse_replay_id("replay:" + data_dir("opencv-left").string());
  EXPECT_EQ(c.pattern, "*");  // a folder plays all its images
  EXPECT_DOUBLE_EQ(c.rate_hz, 15.0);
  for (const char* bad : {"replay:", "replay:@15", "replay:a/*.jpg@", "replay:a/*.jpg@0",
                          "replay:a/*.jpg@fast", "replay:a/*.jpg@15+x", "replay:a/*.jpg@2000"})
    EXPECT_THROW(drivers::parse_replay_id(bad), std::invalid_argument) << bad;
  try {
    drivers::parse_replay_id("replay:a/*.jpg@fast");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("replay:a/*.jpg@fast"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'fast'"), std::string::npos) << e.what();
  }
}

// The 13 shared pairs played as two cameras (the right one 20 ms late, inside the default
// tolerance of half a 10 Hz frame period) go through pairing, detection and selection and must
// reach the very figures the files path reaches on the same pictures. The default selection
// (corners moved 5% of the diagonal) finds 4 of the 13 pairs too close to a kept one; 1% keeps
// all 13.
TEST(StereoLive, ReplayedSharedPairsGiveTheFilesPathFigures) {
  const fs::path data = data_dir("opencv-left");
  ScratchDir dir;
  const auto files =
      run_cli("stereo --images " + q(data) + " --left-pattern 'left*' --right-pattern 'right*' " +
              kBoardArgs + " --out-left " + q(dir.path() / "fL.yml") + " --out-right " +
              q(dir.path() / "fR.yml"));
  ASSERT_EQ(files.exit_code, 0) << files.output;
  const std::string cameras = "stereo --left-camera " + q(replay(data, "left*", "@10")) +
                              " --right-camera " + q(replay(data, "right*", "@10+20")) + " " +
                              kBoardArgs;
  const auto selective = run_cli(cameras + " --out-left " + q(dir.path() / "sL.yml") +
                                 " --out-right " + q(dir.path() / "sR.yml"));
  ASSERT_EQ(selective.exit_code, 0) << selective.output;
  EXPECT_NE(selective.output.find("kept 9 pairs; rejected: 0 unsynchronised, 0 board in one "
                                  "image only, 0 board in neither, 4 too similar"),
            std::string::npos)
      << selective.output;
  const auto live = run_cli(cameras + " --min-move 0.01 --out-left " + q(dir.path() / "L.yml") +
                            " --out-right " + q(dir.path() / "R.yml"));
  ASSERT_EQ(live.exit_code, 0) << live.output;
  const StereoFigures f = figures(files.output), l = figures(live.output);
  std::printf("files path: %d pairs, RMS %.4f px, epipolar %.4f px, baseline %.4f m\n", f.pairs,
              f.rms_px, f.epipolar_px, f.baseline_m);
  std::printf("live path:  %d pairs, RMS %.4f px, epipolar %.4f px, baseline %.4f m\n", l.pairs,
              l.rms_px, l.epipolar_px, l.baseline_m);
  const StereoFigures d = figures(selective.output);
  std::printf("live path, default --min-move: %d pairs, RMS %.4f px, epipolar %.4f px\n", d.pairs,
              d.rms_px, d.epipolar_px);
  EXPECT_EQ(f.pairs, 13);
  EXPECT_EQ(l.pairs, 13) << live.output;
  EXPECT_NEAR(f.rms_px, 0.4448, 5e-4);
  EXPECT_NEAR(f.epipolar_px, 0.2621, 5e-4);
  EXPECT_NEAR(l.rms_px, f.rms_px, 2e-4) << live.output;
  EXPECT_NEAR(l.epipolar_px, f.epipolar_px, 2e-4) << live.output;
  EXPECT_NEAR(l.baseline_m, f.baseline_m, 2e-4) << live.output;
  // Every pair was synchronised (20 ms apart) and none was set aside.
  EXPECT_NE(live.output.find("[1/15] pair 1 (frames 1 + 1, 20.0 ms apart): board found"),
            std::string::npos)
      << live.output;
  EXPECT_NE(live.output.find("examined 13 pairs from"), std::string::npos) << live.output;
  EXPECT_NE(live.output.find("kept 13 pairs; rejected: 0 unsynchronised, 0 board in one image "
                             "only, 0 board in neither, 0 too similar, 0 malformed frames"),
            std::string::npos)
      << live.output;
  EXPECT_NE(live.output.find("stopped: camera replay:"), std::string::npos) << live.output;
  // The same intrinsics in both outputs.
  for (const char* side : {"L", "R"}) {
    const cv::Matx33d a = file_camera_matrix(dir.path() / (std::string("f") + side + ".yml"));
    const cv::Matx33d b = file_camera_matrix(dir.path() / (std::string(side) + ".yml"));
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(a.val[i], b.val[i], 1e-3) << side << " " << i;
  }
}

// A rig whose geometry is known: two cameras (different lenses), the right one 60 mm to the right
// of the left and turned 2 degrees towards it, rendered views of one board pose per pair played
// as two cameras. The right file's pose (left camera = world) must be that baseline and turn. One
// pose is shown twice: the second copy must be refused as too similar.
TEST(StereoLive, RenderedRigRecoversItsKnownBaseline) {
  const Board board = Board::parse("9x6", 0.025);
  SyntheticCamera cams[2];
  cams[0].K = cv::Matx33d(600, 0, 322.5, 0, 600, 241.5, 0, 0, 1);
  cams[1].K = cv::Matx33d(610, 0, 316.2, 0, 608, 236.4, 0, 0, 1);
  cams[0].D = (cv::Mat_<double>(1, 5) << -0.12, 0.05, 0, 0, 0);
  cams[1].D = (cv::Mat_<double>(1, 5) << -0.08, 0.02, 0, 0, 0);
  cams[0].size = cams[1].size = cv::Size(640, 480);
  const double baseline_m = 0.06, toe_in_rad = 2.0 * CV_PI / 180;
  const cv::Vec3d centre_right(baseline_m, 0, 0);  // in the left camera's frame
  cv::Matx33d R_right_left;                        // X_right = R (X_left - centre_right)
  cv::Rodrigues(cv::Vec3d(0, -toe_in_rad, 0), R_right_left);
  const SyntheticRenderer renderers[2] = {SyntheticRenderer(cams[0]), SyntheticRenderer(cams[1])};
  std::mt19937 rng(7);
  ScratchDir dir;
  const fs::path pics = dir.path() / "pictures";
  fs::create_directories(pics);
  const auto inside = [&](const SyntheticCamera& cam, const BoardPose& p) {
    const auto c = project_corners(cam, board, p);
    const float m = 40;  // the margin square and the detector's window stay inside too
    return std::all_of(c.begin(), c.end(), [&](const cv::Point2f& q) {
      return q.x > m && q.y > m && q.x < cam.size.width - m && q.y < cam.size.height - m;
    });
  };
  const int kPairs = 12;
  int written = 0;
  BoardPose first;
  while (written < kPairs) {
    BoardPose pl = written == kPairs - 1 ? first : random_board_pose(cams[0], board, rng, 30.0);
    cv::Matx33d Rl;
    cv::Rodrigues(pl.rvec, Rl);
    BoardPose pr;
    cv::Rodrigues(R_right_left * Rl, pr.rvec);
    pr.tvec = R_right_left * (pl.tvec - centre_right);
    if (!inside(cams[0], pl) || !inside(cams[1], pr)) continue;
    if (written == 0) first = pl;
    char name[32];
    for (int s = 0; s < 2; ++s) {
      std::snprintf(name, sizeof name, "%s%02d.png", s == 0 ? "left" : "right", written);
      std::ofstream(pics / name, std::ios::binary)
          << encode_png(renderers[s].render(board, s == 0 ? pl : pr, 0.8, 1.0, rng));
    }
    ++written;
  }
  const auto r =
      run_cli("stereo --left-camera " + q(replay(pics, "left*", "@30")) + " --right-camera " +
              q(replay(pics, "right*", "@30")) + " " + kBoardArgs + " --out-left " +
              q(dir.path() / "L.yml") + " --out-right " + q(dir.path() / "R.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("kept 11 pairs; rejected: 0 unsynchronised, 0 board in one image "
                          "only, 0 board in neither, 1 too similar"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("pair 12 (frames 12 + 12, 0.0 ms apart): board found / board found, "
                          "too close to a kept pair"),
            std::string::npos)
      << r.output;
  const CalibrationFile left = read_calibration_file(dir.path() / "L.yml");
  const CalibrationFile right = read_calibration_file(dir.path() / "R.yml");
  ASSERT_TRUE(left.camera_pose && right.camera_pose);
  // T_world_right with the left camera as world: centre at centre_right, R = R_right_left^T.
  const core::Pose& T = *right.camera_pose;
  const cv::Vec3d t(T.t(0), T.t(1), T.t(2));
  const double centre_err_mm = 1000 * cv::norm(t - centre_right);
  cv::Matx33d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = T.R(i, j);
  cv::Vec3d dr;
  cv::Rodrigues(R * R_right_left, dr);  // identity when R == R_right_left^T
  const double turn_err_deg = cv::norm(dr) * 180 / CV_PI;
  const StereoFigures f = figures(r.output);
  std::printf(
      "rendered rig: %d pairs, RMS %.4f px, epipolar %.4f px, baseline %.5f m (true %.5f), "
      "right camera centre %.3f mm and %.4f deg from the truth; fx %.2f / %.2f (true 600 / "
      "610)\n",
      f.pairs, f.rms_px, f.epipolar_px, f.baseline_m, baseline_m, centre_err_mm, turn_err_deg,
      core::to_opencv(left.pinhole).fx, core::to_opencv(right.pinhole).fx);
  EXPECT_EQ(f.pairs, 11);
  EXPECT_LT(f.rms_px, 0.15);
  EXPECT_LT(centre_err_mm, 1.0);
  EXPECT_LT(turn_err_deg, 0.1);
  EXPECT_NEAR(core::to_opencv(left.pinhole).fx, 600, 2.0);
  EXPECT_NEAR(core::to_opencv(right.pinhole).fx, 610, 2.0);
  EXPECT_TRUE(left.camera_pose->t.norm() < 1e-12);  // the left camera is the origin
}

TEST(StereoLive, AnUnopenableCameraIsNamedAndNothingIsWritten) {
  const fs::path data = data_dir("opencv-left");
  ScratchDir dir;
  const std::string outs =
      " --out-left " + q(dir.path() / "L.yml") + " --out-right " + q(dir.path() / "R.yml");
  const auto r = run_cli("stereo --left-camera " + q(replay(data, "left*")) +
                         " --right-camera /dev/video99 " + kBoardArgs + outs);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("error: cannot open camera /dev/video99 (--right-camera)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("No such file or directory"), std::string::npos) << r.output;
  const auto l = run_cli("stereo --left-camera replay:/no/such/folder/left*.jpg --right-camera " +
                         q(replay(data, "right*")) + " " + kBoardArgs + outs);
  EXPECT_EQ(l.exit_code, 2) << l.output;
  EXPECT_NE(l.output.find("error: cannot open camera replay:/no/such/folder/left*.jpg "
                          "(--left-camera): replay camera replay:/no/such/folder/left*.jpg: "
                          "/no/such/folder: not a folder"),
            std::string::npos)
      << l.output;
  EXPECT_TRUE(dir.listing().empty());
}

TEST(StereoLive, ExactlyOneSourceOfPairs) {
  const fs::path data = data_dir("opencv-left");
  ScratchDir dir;
  const std::string outs =
      " --out-left " + q(dir.path() / "L.yml") + " --out-right " + q(dir.path() / "R.yml");
  const auto both = run_cli("stereo --images " + q(data) +
                            " --left-camera mock --right-camera mock " + kBoardArgs + outs);
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_NE(both.output.find("--images and --left-camera/--right-camera exclude each other"),
            std::string::npos)
      << both.output;
  const auto one = run_cli("stereo --left-camera mock " + kBoardArgs + outs);
  EXPECT_EQ(one.exit_code, 2) << one.output;
  EXPECT_NE(one.output.find("--right-camera is missing"), std::string::npos) << one.output;
  const auto none = run_cli("stereo " + kBoardArgs + outs);
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("give either --images DIR (pairs from files) or both --left-camera"),
            std::string::npos)
      << none.output;
  EXPECT_TRUE(dir.listing().empty());
}

TEST(StereoLive, CamerasOfDifferentSizesAreRefusedNamingBoth) {
  ScratchDir dir;
  const auto r =
      run_cli("stereo --left-camera " + q(replay(data_dir("opencv-left"), "left0[1-3]*")) +
              " --right-camera mock:320x240 " + kBoardArgs + " --out-left " +
              q(dir.path() / "L.yml") + " --out-right " + q(dir.path() / "R.yml"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("delivers 640x480 but camera mock:320x240 delivers 320x240; a stereo "
                          "calibration needs both cameras at one size; nothing written"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(dir.listing().empty());
}

// Two 10 Hz streams 50 ms apart with a 20 ms tolerance: no frame has a partner. Each is set aside
// in turn (the older one of the two waiting), 25 of the 26, until the left stream ends.
TEST(StereoLive, UnsynchronisedStreamsAreCountedAndReported) {
  const fs::path data = data_dir("opencv-left");
  ScratchDir dir;
  const auto r = run_cli("stereo --left-camera " + q(replay(data, "left*", "@10")) +
                         " --right-camera " + q(replay(data, "right*", "@10+50")) + " " +
                         kBoardArgs + " --sync-tolerance 20 --out-left " + q(dir.path() / "L.yml") +
                         " --out-right " + q(dir.path() / "R.yml"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("frame 1 from left camera replay:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("set aside: unsynchronised, 50.0 ms from the other camera's frame "
                          "(tolerance 20.0 ms)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("examined 0 pairs"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rejected: 25 unsynchronised"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error: no synchronised pair in 13 + 13 frames from cameras"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(dir.listing().empty());
}

// The left camera sees the 9x6 board, the right one a 7x7 board: every pair has the board in one
// image only; nothing is calibrated and nothing written.
TEST(StereoLive, NoBoardInBothImagesOfAnyPairIsAFailure) {
  ScratchDir dir;
  const auto r = run_cli(
      "stereo --left-camera " + q(replay(data_dir("opencv-left"), "left0[1-3]*")) +
      " --right-camera " + q(replay(data_dir("webcam-7x7"), "left0[1-3]*")) + " " + kBoardArgs +
      " --out-left " + q(dir.path() / "L.yml") + " --out-right " + q(dir.path() / "R.yml"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  // The right verdict is "no board", or "detection timed out" when a starved CPU lets the SB
  // detector's search run past its deadline: either way not found, so the board is in one image.
  for (int i = 1; i <= 3; ++i) {
    const std::string n = std::to_string(i);
    const std::string line = line_starting(r.output, "[0/15] pair " + n + " (frames " + n + " + " +
                                                         n + ", 0.0 ms apart): board found / ");
    EXPECT_NE(line.find(", board in one image only;"), std::string::npos) << i << "\n" << r.output;
  }
  EXPECT_NE(r.output.find("3 board in one image only"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("error: no 9x6 board found in both images of any of the 3 pairs from "
                          "cameras replay:"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(dir.listing().empty());
}

}  // namespace
}  // namespace hd::calib::test

namespace hd::calib::test {
namespace {

// The replay driver through the CameraSource interface: every picture, in order, stamped on the
// shared grid (epoch + offset + k / rate), then the stream ends. The consumer waits for frames,
// never for time.
TEST(ReplayCamera, PlaysEveryPictureInOrderOnItsGridThenEnds) {
  auto cam = drivers::make_camera_source(
      "replay:" + (data_dir("opencv-left") / "left0[1-4]*").string() + "@50+3", load_replay_images);
  cam->open();
  EXPECT_EQ(cam->format().width_px, 640);
  EXPECT_DOUBLE_EQ(cam->format().frame_rate_hz, 50.0);
  cam->start();
  std::vector<int64_t> stamps_ns;
  std::vector<uint64_t> sequences;
  for (;;) {
    const bool stopped = cam->state() == drivers::SourceState::kClosed;
    if (cam->frames().fetch()) {
      const drivers::Frame& f = cam->frames().latest();
      sequences.push_back(f.sequence);
      stamps_ns.push_back(f.host_timestamp_ns);
      EXPECT_TRUE(f.device_time_trusted);
      EXPECT_EQ(f.format, drivers::PixelFormat::kRgba8);
      EXPECT_EQ(f.width, 640);
    } else if (stopped) {
      break;
    } else {
      std::this_thread::yield();
    }
  }
  cam->stop();
  ASSERT_EQ(sequences, (std::vector<uint64_t>{0, 1, 2, 3}));
  for (std::size_t k = 1; k < stamps_ns.size(); ++k)
    EXPECT_EQ(stamps_ns[k] - stamps_ns[k - 1], 20'000'000) << k;  // 50 Hz
  EXPECT_EQ(cam->dropped_frames(), 0u);
  // A folder that does not exist is refused at open.
  EXPECT_THROW(drivers::make_camera_source("replay:/no/such/dir/*.png", load_replay_images)->open(),
               drivers::DeviceError);
}

}  // namespace
}  // namespace hd::calib::test
