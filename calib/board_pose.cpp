#include "calib/board_pose.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "calib/corner_detector.h"
#include "core/opencv_pixels.h"

namespace hd::calib {

cv::Matx33d camera_matrix(const core::Pinhole& pinhole) {
  const core::OpenCvIntrinsics p = core::to_opencv(pinhole);
  return {p.fx, 0, p.cx, 0, p.fy, p.cy, 0, 0, 1};
}

cv::Mat distortion_row(const core::Pinhole& p) {
  cv::Mat d(1, std::max(p.distortion_count, 4), CV_64F, cv::Scalar(0));
  for (int i = 0; i < p.distortion_count; ++i) d.at<double>(0, i) = p.distortion[i];
  return d;
}

namespace {

// Corners relabelled as if the board were turned by `turn` quarter turns.
std::vector<cv::Point2f> relabel(const std::vector<cv::Point2f>& c, int cols, int rows, int turn) {
  std::vector<cv::Point2f> out(c.size());
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) {
      int sr = r, sk = k;
      switch (turn) {
        case 1:
          sr = cols - 1 - k;
          sk = r;
          break;  // square boards only (cols == rows)
        case 2:
          sr = rows - 1 - r;
          sk = cols - 1 - k;
          break;
        case 3:
          sr = k;
          sk = rows - 1 - r;
          break;
        default:
          break;
      }
      out[static_cast<std::size_t>(r * cols + k)] = c[static_cast<std::size_t>(sr * cols + sk)];
    }
  return out;
}

double mean_at(const cv::Mat& gray, cv::Point2f p) {
  const cv::Rect box(cvRound(p.x) - 1, cvRound(p.y) - 1, 3, 3);
  const cv::Rect clipped = box & cv::Rect(0, 0, gray.cols, gray.rows);
  if (clipped.area() == 0) return 0;
  return cv::mean(gray(clipped))[0];
}

core::Pose to_pose(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  core::Pose T_cam_board;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) T_cam_board.R(i, j) = R(i, j);
    T_cam_board.t(i) = tvec[i];
  }
  return T_cam_board;
}

std::string describe(const PoseCandidate& c) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "turn %d deg: camera at (%.3f, %.3f, %.3f) m, rms %.2f px%s",
                c.turn_deg, c.camera_pose.t.x(), c.camera_pose.t.y(), c.camera_pose.t.z(), c.rms_px,
                c.colour_ok ? "" : ", origin square not black");
  return buf;
}

}  // namespace

PoseResult estimate_camera_pose(const cv::Mat& gray, const Board& board,
                                const core::Pinhole& intrinsics, const core::Pose& T_world_board,
                                const PoseOptions& opt) {
  const Detection det = detect_corners(gray, board, DetectorOptions{});
  if (!det.found())
    throw PoseRefused("no " + std::to_string(board.cols) + "x" + std::to_string(board.rows) +
                      " board found in the pose image (" + det.describe() + ")");
  const cv::Matx33d K = camera_matrix(intrinsics);
  const cv::Mat D = distortion_row(intrinsics);
  const auto obj = board.object_points();
  const bool square = board.cols == board.rows;

  std::vector<PoseCandidate> cands;
  std::vector<std::vector<cv::Point2f>> labelled;
  for (int turn = 0; turn < 4; ++turn) {
    if (!square && turn % 2 == 1) continue;
    auto pts = relabel(det.corners, board.cols, board.rows, turn);
    std::vector<cv::Mat> rvecs, tvecs;
    cv::solvePnPGeneric(obj, pts, K, D, rvecs, tvecs, false, cv::SOLVEPNP_IPPE);
    if (rvecs.empty()) continue;
    // IPPE returns the planar pose pair sorted by error; the first one is the fit. Its error is
    // recomputed per point (OpenCV's figure is per coordinate, sqrt(2) smaller) so it compares
    // with calibrate's per-view RMS.
    PoseCandidate c;
    c.turn_deg = 90 * turn;
    std::vector<cv::Point2f> proj;
    cv::projectPoints(obj, rvecs[0], tvecs[0], K, D, proj);
    double sum = 0;
    for (std::size_t i = 0; i < proj.size(); ++i) {
      const cv::Point2f e = proj[i] - pts[i];
      sum += e.dot(e);
    }
    c.rms_px = std::sqrt(sum / static_cast<double>(proj.size()));
    const core::Pose T_cam_board = to_pose(cv::Vec3d(rvecs[0]), cv::Vec3d(tvecs[0]));
    c.camera_pose = T_world_board * T_cam_board.inverse();
    // Colour of the first inner square vs the square beside it along the first row.
    const auto at = [&](int r, int k) { return pts[static_cast<std::size_t>(r * board.cols + k)]; };
    const double origin_sq = mean_at(gray, (at(0, 0) + at(0, 1) + at(1, 0) + at(1, 1)) * 0.25f);
    const double next_sq = mean_at(gray, (at(0, 1) + at(0, 2) + at(1, 1) + at(1, 2)) * 0.25f);
    c.colour_ok = origin_sq < next_sq;
    c.colour_contrast = std::abs(origin_sq - next_sq);
    cands.push_back(c);
    labelled.push_back(std::move(pts));
  }
  if (cands.empty()) throw PoseRefused("solvePnP (IPPE) found no pose for the detected corners");

  std::vector<std::size_t> alive;
  for (std::size_t i = 0; i < cands.size(); ++i)
    if (cands[i].colour_ok) alive.push_back(i);
  std::string cue = "square colour (origin square black)";
  if (alive.empty())
    throw PoseRefused("square colour cue failed: no labelling puts a black square at the origin");

  if (alive.size() > 1) {
    std::string list;
    for (auto i : alive) list += "\n  " + describe(cands[i]);
    if (!opt.expect_camera_dir_world)
      throw PoseRefused("the board looks the same turned by 180" +
                        std::string(square ? " (or 90)" : "") +
                        " deg and nothing tells the turns apart; candidates:" + list +
                        "\npass --expect-camera-dir X,Y,Z (rough world direction from the board to "
                        "the camera) to choose");
    const cv::Vec3d dir = cv::normalize(*opt.expect_camera_dir_world);
    const Eigen::Vector3d centre = T_world_board.to_world(
        {0.5 * (board.cols - 1) * board.square_m, 0.5 * (board.rows - 1) * board.square_m, 0});
    std::vector<std::pair<double, std::size_t>> scored;
    for (auto i : alive) {
      const Eigen::Vector3d v = (cands[i].camera_pose.t - centre).normalized();
      scored.emplace_back(v.x() * dir[0] + v.y() * dir[1] + v.z() * dir[2], i);
    }
    std::sort(scored.rbegin(), scored.rend());
    if (scored[0].first - scored[1].first < 0.3)
      throw PoseRefused("--expect-camera-dir does not separate the candidates (cosines " +
                        std::to_string(scored[0].first) + " vs " + std::to_string(scored[1].first) +
                        "):" + list);
    alive = {scored[0].second};
    cue += " + expected camera direction";
  }
  PoseResult res;
  res.camera_pose = cands[alive[0]].camera_pose;
  res.rms_px = cands[alive[0]].rms_px;
  res.cue = cue;
  res.candidates = cands;
  res.corners = labelled[alive[0]];
  return res;
}

}  // namespace hd::calib
