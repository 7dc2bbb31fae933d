// The pixel convention from file to screen (issue 11 item 5): chessboard views rendered by the
// station's own mesh rasteriser from a known core::Pinhole, calibrated by the hybrid-calib program,
// read back through read_calibration_file, must give that Pinhole (and `pose` its pose), not one
// half a pixel off.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "calib/board.h"
#include "calib/calibration_file.h"
#include "calib/corner_detector.h"
#include "calib/synthetic_views.h"
#include "core/pinhole.h"
#include "core/pose.h"
#include "render/compositor/mesh_rasterizer.h"
#include "render/compositor/synthetic_scene.h"
#include "test_support.h"

namespace hd::calib::test {
namespace {

constexpr int kSupersample = 4;
constexpr int kTexelsPerSquare = 32;
constexpr int kViews = 40;

// The printed board as one textured quad in the board's frame (Board::object_points: origin at
// the first inner corner, x along a row, y along a column): squares (cols + 1) x (rows + 1),
// the origin's diagonal square black, one white square of margin around.
render::TexturedMesh board_mesh(const Board& b) {
  const int sq_x = b.cols + 3, sq_y = b.rows + 3;  // squares incl. the margin
  render::TexturedMesh m;
  m.texture.allocate(sq_x * kTexelsPerSquare, sq_y * kTexelsPerSquare);
  for (int y = 0; y < m.texture.height; ++y)
    for (int x = 0; x < m.texture.width; ++x) {
      const int su = x / kTexelsPerSquare - 2, sv = y / kTexelsPerSquare - 2;  // square index
      const bool margin = su < -1 || sv < -1 || su > b.cols - 1 || sv > b.rows - 1;
      const uint8_t v = margin || ((su + sv) & 1) ? 225 : 30;
      uint8_t* p = m.texture.pixel(x, y);
      p[0] = p[1] = p[2] = v;
      p[3] = 255;
    }
  const float s = static_cast<float>(b.square_m);
  const float x0 = -2 * s, y0 = -2 * s, x1 = x0 + sq_x * s, y1 = y0 + sq_y * s;
  m.positions_m = {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// The view of `scene` from a camera at T_world_cam: the mesh rasteriser at kSupersample times the
// resolution (the same lens: focal lengths and principal point scaled, so fine pixel (i, j)
// covers [i, i+1]/k in core's continuous coordinates), box-filtered down to the camera's pixels.
cv::Mat render_gray(const render::SyntheticScene& scene, const core::Pinhole& cam,
                    const core::Pose& T_world_cam, double blur_sigma_px = 0.8) {
  core::Pinhole fine = cam;
  fine.fx *= kSupersample;
  fine.fy *= kSupersample;
  fine.cx *= kSupersample;
  fine.cy *= kSupersample;
  fine.width *= kSupersample;
  fine.height *= kSupersample;
  std::vector<uint8_t> rgba(static_cast<std::size_t>(fine.width) * fine.height * 4, 0);
  std::vector<float> depth(static_cast<std::size_t>(fine.width) * fine.height, 0.f);
  render::MeshRasterizer r;
  r.prepare(scene, fine, T_world_cam, 0.01, 100.0);
  r.draw_rows(scene, {rgba.data(), depth.data(), fine.width, fine.height}, 0, fine.height);
  cv::Mat big(fine.height, fine.width, CV_8UC4, rgba.data());
  cv::Mat gray_big, gray;
  cv::cvtColor(big, gray_big, cv::COLOR_RGBA2GRAY);
  for (std::size_t i = 0; i < depth.size(); ++i)  // where no board is drawn: a grey surround
    if (depth[i] == 0.f) gray_big.data[i] = 128;
  cv::resize(gray_big, gray, cv::Size(cam.width, cam.height), 0, 0, cv::INTER_AREA);
  // A lens's blur (symmetric, so it moves no corner) keeps cornerSubPix off the staircase edges.
  if (blur_sigma_px > 0) cv::GaussianBlur(gray, gray, cv::Size(0, 0), blur_sigma_px);
  return gray;
}

core::Pose pose_from_cv(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  core::Pose p;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p.R(i, j) = R(i, j);
    p.t(i) = tvec[i];
  }
  return p;
}

// The board with its white margin at least 8 px inside the image.
bool whole_board_inside(const SyntheticCamera& cam, const Board& b, const BoardPose& p) {
  const auto s = static_cast<float>(b.square_m);
  const std::vector<cv::Point3f> outline = {{-2 * s, -2 * s, 0},
                                            {(b.cols + 1) * s, -2 * s, 0},
                                            {(b.cols + 1) * s, (b.rows + 1) * s, 0},
                                            {-2 * s, (b.rows + 1) * s, 0}};
  std::vector<cv::Point2f> img;
  cv::projectPoints(outline, p.rvec, p.tvec, cam.K, cam.D, img);
  for (const auto& q : img)
    if (q.x < 8 || q.y < 8 || q.x > cam.size.width - 8 || q.y > cam.size.height - 8) return false;
  return true;
}

// The known camera: off-centre principal point with fractional parts, so a half-pixel slip, a
// swapped axis or a rounding shows; no distortion (the rasteriser draws an ideal pinhole).
core::Pinhole known_camera() {
  core::Pinhole k;
  k.fx = 530.0;
  k.fy = 530.0;
  k.cx = 328.3;
  k.cy = 236.8;
  k.width = 640;
  k.height = 480;
  return k;
}

struct Rendered {
  ScratchDir dir;
  Board board = Board::parse("9x6", 0.025);
  render::SyntheticScene scene;
};

TEST(PixelConvention, CalibrationFileFromRenderedViewsReadsBackAsTheRenderedPinhole) {
  const core::Pinhole truth = known_camera();
  Rendered r;
  r.scene.meshes.push_back(board_mesh(r.board));
  // Board poses from the calibration benchmark's generator (any well-spread set does).
  SyntheticCamera gen{cv::Matx33d(truth.fx, 0, truth.cx, 0, truth.fy, truth.cy, 0, 0, 1),
                      cv::Mat::zeros(1, 5, CV_64F), cv::Size(truth.width, truth.height)};
  std::mt19937 rng(5);
  const auto images = r.dir.path() / "views";
  fs::create_directories(images);
  for (int i = 0; i < kViews;) {
    const BoardPose bp = random_board_pose(gen, r.board, rng, 40.0);
    if (!whole_board_inside(gen, r.board, bp)) continue;  // the generator's last resort is not
    // The board frame is the world frame here: T_world_cam = T_cam_board^-1.
    const core::Pose T_world_cam = pose_from_cv(bp.rvec, bp.tvec).inverse();
    char name[32];
    std::snprintf(name, sizeof name, "view%02d.png", i++);
    ASSERT_TRUE(cv::imwrite((images / name).string(), render_gray(r.scene, truth, T_world_cam)));
  }
  const auto out = r.dir.path() / "cam.yml";
  const auto run = run_cli("intrinsics --images " + q(images) + " --board 9x6 --square 0.025 " +
                           "--model 5 --out " + q(out));
  ASSERT_EQ(run.exit_code, 0) << run.output;

  const CalibrationFile f = read_calibration_file(out);
  cv::FileStorage fs(out.string(), cv::FileStorage::READ);
  cv::Mat sd;
  fs["intrinsics_std_dev"] >> sd;
  ASSERT_GE(sd.total(), 4u);
  sd.convertTo(sd, CV_64F);
  const double s_cx = sd.at<double>(2), s_cy = sd.at<double>(3);
  const double e_cx = f.pinhole.cx - truth.cx, e_cy = f.pinhole.cy - truth.cy;
  RecordProperty("cx_error_px", std::to_string(e_cx));
  RecordProperty("cy_error_px", std::to_string(e_cy));
  std::printf("cx %.4f (truth %.4f, sigma %.4f)  cy %.4f (truth %.4f, sigma %.4f)\n", f.pinhole.cx,
              truth.cx, s_cx, f.pinhole.cy, truth.cy, s_cy);
  // Within the reported uncertainty (1 sigma, as the issue asks: the views are rendered and the
  // calibration is deterministic, so this is a fixed figure, the same in the plain and the
  // sanitizer build: cx -0.177 px against sigma 0.183, cy -0.027 against 0.131)...
  EXPECT_LE(std::abs(e_cx), s_cx) << run.output;
  EXPECT_LE(std::abs(e_cy), s_cy) << run.output;
  // ... and clearly not the half-pixel slip this test exists for.
  EXPECT_LT(std::abs(e_cx), 0.25);
  EXPECT_LT(std::abs(e_cy), 0.25);
  EXPECT_NEAR(f.pinhole.fx, truth.fx, 3.0 * sd.at<double>(0) + 0.05);
  EXPECT_NEAR(f.pinhole.fy, truth.fy, 3.0 * sd.at<double>(1) + 0.05);
  // The file itself holds OpenCV's numbers (what OpenCV and ROS tools expect).
  const cv::Matx33d K = file_camera_matrix(out);
  EXPECT_NEAR(K(0, 2), truth.cx - 0.5, 0.25);
  EXPECT_NEAR(K(1, 2), truth.cy - 0.5, 0.25);

  // `pose`: a board at a known workspace pose, seen from a known camera pose, through the
  // calibration just written.
  core::Pose T_world_board;
  T_world_board.R =
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, -0.4).normalized()).toRotationMatrix();
  T_world_board.t = {0.40, -0.10, 0.90};
  const Eigen::Vector3d centre_board(4 * 0.025, 2.5 * 0.025, 0.0);
  const Eigen::Vector3d centre_w = T_world_board.to_world(centre_board);
  // The true camera 0.45 m from the board centre, looking at a point 2 cm off it (so the
  // principal point matters), rolled a little.
  core::Pose T_world_cam_true;
  const Eigen::Vector3d eye = centre_w + T_world_board.R * Eigen::Vector3d(0.06, -0.04, -0.45);
  const Eigen::Vector3d z = (centre_w + Eigen::Vector3d(0.02, 0.01, 0) - eye).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();  // image y ~ world y
  T_world_cam_true.R.col(0) = x;
  T_world_cam_true.R.col(1) = z.cross(x);
  T_world_cam_true.R.col(2) = z;
  T_world_cam_true.R =
      T_world_cam_true.R * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_world_cam_true.t = eye;
  ASSERT_TRUE(T_world_cam_true.valid(1e-9));
  render::SyntheticScene placed = r.scene;
  for (auto& p : placed.meshes[0].positions_m)
    p = T_world_board.to_world(p.cast<double>()).cast<float>();
  const auto pose_img = r.dir.path() / "pose.png";
  ASSERT_TRUE(cv::imwrite(pose_img.string(), render_gray(placed, truth, T_world_cam_true)));
  cv::Vec3d rvec;
  {
    cv::Matx33d R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = T_world_board.R(i, j);
    cv::Rodrigues(R, rvec);
  }
  char board_pose[160];
  std::snprintf(board_pose, sizeof board_pose, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g",
                T_world_board.t.x(), T_world_board.t.y(), T_world_board.t.z(), rvec[0], rvec[1],
                rvec[2]);
  const auto pose_out = r.dir.path() / "pose.yml";
  const auto prun =
      run_cli("pose --intrinsics " + q(out) + " --image " + q(pose_img) +
              " --board 9x6 --square 0.025 --board-pose " + board_pose + " --out " + q(pose_out));
  ASSERT_EQ(prun.exit_code, 0) << prun.output;
  const CalibrationFile p = read_calibration_file(pose_out);
  ASSERT_TRUE(p.camera_pose);
  // The pose file carries the same Pinhole through the same conversion.
  EXPECT_NEAR(p.pinhole.cx, f.pinhole.cx, 1e-9);
  EXPECT_NEAR(p.pinhole.cy, f.pinhole.cy, 1e-9);
  const double dpos_m = (p.camera_pose->t - T_world_cam_true.t).norm();
  const double dang_rad =
      Eigen::AngleAxisd(p.camera_pose->R.transpose() * T_world_cam_true.R).angle();
  std::printf("pose: position error %.3f mm, orientation error %.4f mrad\n", 1e3 * dpos_m,
              1e3 * dang_rad);
  EXPECT_LT(dpos_m, 1.5e-3);
  // Where the pose file says the camera sees the board's corners (its pose and Pinhole, through
  // core's projection) against where the rendering camera drew them: a half-pixel slip between
  // the file, board_pose and core shows here in full.
  double worst_px = 0;
  for (const auto& o : r.board.object_points()) {
    const Eigen::Vector3d X = T_world_board.to_world(Eigen::Vector3d(o.x, o.y, o.z));
    const Eigen::Vector2d a = truth.project(T_world_cam_true.to_camera(X));
    const Eigen::Vector2d b = p.pinhole.project(p.camera_pose->to_camera(X));
    worst_px = std::max(worst_px, (a - b).norm());
  }
  std::printf("pose: worst corner displacement %.3f px\n", worst_px);
  EXPECT_LT(worst_px, 0.25);
}

// Issue 13 item 6: one view in which OpenCV's SB detector reports the 9x6 pattern as part of a
// larger board (it does so for some steep views of a board with a white margin) made the whole
// run refuse. SB is now asked only where the checker visibly goes on past the pattern's edges,
// so that view calibrates like the others; a view that really shows a larger board is dropped by
// name when it is alone, and when the views agree (--board 8x6 for a 9x6 board), --board is
// wrong and nothing is written.
TEST(LargerBoard, ALoneViewIsDroppedByNameTheViewsAgreeingIsAnError) {
  const core::Pinhole truth = known_camera();
  Rendered r;
  r.scene.meshes.push_back(board_mesh(r.board));
  render::SyntheticScene larger_scene;  // a 10x6 board: one column more than --board says
  larger_scene.meshes.push_back(board_mesh(Board::parse("10x6", 0.025)));
  SyntheticCamera gen{cv::Matx33d(truth.fx, 0, truth.cx, 0, truth.fy, truth.cy, 0, 0, 1),
                      cv::Mat::zeros(1, 5, CV_64F), cv::Size(truth.width, truth.height)};
  const auto images = r.dir.path() / "views";
  fs::create_directories(images);
  std::mt19937 rng(11);
  DetectorOptions plain;
  plain.check_larger = false;
  // A steep view of the 9x6 board that trips SB's larger-board report and that the classic
  // detector finds: searched among steep random views.
  bool tripped = false;
  for (int attempt = 0; attempt < 200 && !tripped; ++attempt) {
    const BoardPose bp = random_board_pose(gen, r.board, rng, 45.0);
    const cv::Mat g = render_gray(r.scene, truth, pose_from_cv(bp.rvec, bp.tvec).inverse(), 0.0);
    if (larger_board_corners(g, r.board) > 0 && detect_corners(g, r.board, plain).found()) {
      ASSERT_TRUE(cv::imwrite((images / "view00.png").string(), g));
      tripped = true;
    }
  }
  ASSERT_TRUE(tripped) << "no rendered view trips SB's larger-board report";
  // A view of the 10x6 board in which the classic detector finds a 9x6 part.
  DetectorOptions classic = plain;
  classic.use_sb_fallback = false;
  bool larger = false;
  for (int attempt = 0; attempt < 200 && !larger; ++attempt) {
    const BoardPose bp = random_board_pose(gen, r.board, rng, 30.0);
    const cv::Mat g = render_gray(larger_scene, truth, pose_from_cv(bp.rvec, bp.tvec).inverse());
    if (detect_corners(g, r.board, classic).found() && larger_board_corners(g, r.board) > 0) {
      ASSERT_TRUE(cv::imwrite((images / "larger00.png").string(), g));
      larger = true;
    }
  }
  ASSERT_TRUE(larger) << "no rendered view of the 10x6 board shows a 9x6 part";
  for (int i = 1; i < 12;) {
    const BoardPose bp = random_board_pose(gen, r.board, rng, 35.0);
    if (!whole_board_inside(gen, r.board, bp)) continue;
    const cv::Mat g = render_gray(r.scene, truth, pose_from_cv(bp.rvec, bp.tvec).inverse());
    char name[32];
    std::snprintf(name, sizeof name, "view%02d.png", i++);
    ASSERT_TRUE(cv::imwrite((images / name).string(), g));
  }
  const auto out = r.dir.path() / "cam.yml";
  const auto run =
      run_cli("intrinsics --images " + q(images) + " --board 9x6 --square 0.025 --out " + q(out));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("WARNING [larger_board_view] larger00.png"), std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("WARNING [larger_board_view] view"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("calibrated 12 views"), std::string::npos) << run.output;
  cv::FileStorage fs(out.string(), cv::FileStorage::READ);
  std::vector<std::string> codes, names;
  fs["warning_codes"] >> codes;
  fs["view_names"] >> names;
  EXPECT_NE(std::find(codes.begin(), codes.end(), "larger_board_view"), codes.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "larger00.png"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "view00.png"), names.end());
  const CalibrationFile f = read_calibration_file(out);
  EXPECT_NEAR(f.pinhole.cx, truth.cx, 3.0);
  EXPECT_NEAR(f.pinhole.fx, truth.fx, 3.0);

  // The same views with --board 8x6: wherever the 8x6 pattern is found it is inside the 9x6
  // board, the views agree, and nothing is written (BadInput.WrongBoardSize shows the message on
  // real views, where the classic detector finds 8x6 parts).
  const auto out8 = r.dir.path() / "cam8.yml";
  const auto wrong =
      run_cli("intrinsics --images " + q(images) + " --board 8x6 --square 0.025 --out " + q(out8));
  EXPECT_NE(wrong.exit_code, 0) << wrong.output;
  EXPECT_FALSE(fs::exists(out8));
}

}  // namespace
}  // namespace hd::calib::test
