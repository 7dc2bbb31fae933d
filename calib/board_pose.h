#pragma once
// The camera pose P_c in the workspace from one view of a board at a known workspace pose.

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calib/board.h"
#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::calib {

/// Thrown when the view cannot give one trustworthy pose (no board, unresolved ambiguity).
class PoseRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The board's own frame: origin at the first inner corner, x along a row, y along a column,
/// z = x cross y (into the board's back). A chessboard looks the same after a 180 deg turn (and
/// after 90 deg if square), so a detector may number the corners from any of those starts.
/// Cues, in order:
///  1. square colour: the board's ORIGIN is the inner corner whose diagonal inner square (towards
///     corner (1,1)) is BLACK. This removes the turns that swap square colours (180 deg on boards
///     with an odd number of squares along one side and even along the other, e.g. 9x6 inner
///     corners; 90 deg on square boards).
///  2. `expect_camera_dir_world`: a rough world direction from the board towards the camera;
///     the candidate whose camera lies most in that direction wins if it leads the runner-up by
///     > 0.3 in cosine.
/// If candidates remain after these, PoseRefused lists them. Never a silent pick.
struct PoseOptions {
  std::optional<cv::Vec3d> expect_camera_dir_world;
};

struct PoseCandidate {
  int turn_deg = 0;            ///< relabelling of the detected corners (0, 90, 180, 270)
  bool colour_ok = false;      ///< origin square is black in this labelling
  double colour_contrast = 0;  ///< |origin square - neighbour square| intensity (0..255)
  core::Pose camera_pose;      ///< T_world_cam
  double rms_px = 0.0;
};

struct PoseResult {
  core::Pose camera_pose;  ///< T_world_cam
  double rms_px = 0.0;
  std::string cue;  ///< how the choice was made, for the file and the log
  std::vector<PoseCandidate> candidates;
  std::vector<cv::Point2f> corners;  ///< detected, relabelled to the chosen board frame
};

/// `gray` 8-bit; `T_world_board` the board's workspace pose. Throws PoseRefused.
PoseResult estimate_camera_pose(const cv::Mat& gray, const Board& board,
                                const core::Pinhole& intrinsics, const core::Pose& T_world_board,
                                const PoseOptions& opt);

/// OpenCV's camera matrix (pixel centres at integers, core::to_opencv) and distortion row of a
/// Pinhole.
cv::Matx33d camera_matrix(const core::Pinhole& p);
cv::Mat distortion_row(const core::Pinhole& p);

}  // namespace hd::calib
