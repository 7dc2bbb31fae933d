#pragma once
// The calibration file the station and hybrid-geom read: OpenCV FileStorage YAML with the keys of
// OpenCV's calibration sample, plus our quality figures and (after `pose`) the camera pose.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "calib/board.h"
#include "calib/coverage.h"
#include "calib/cross_validation.h"
#include "calib/intrinsics_calibration.h"
#include "calib/quality_warnings.h"
#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::calib {

/// A file that is missing, unparsable or lacks/garbles a key. The message names file and key.
class CalibrationFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CalibrationFile {
  core::Pinhole pinhole;
  std::optional<core::Pose> camera_pose;  ///< T_world_cam, present after `hybrid-calib pose`
  double avg_reprojection_error_px = 0.0;
  std::vector<std::string> warnings;
};

/// Reads camera_matrix, distortion_coefficients (4, 5 or 8 terms), image_width, image_height and,
/// if present, camera_pose_R / camera_pose_t (both or neither; R must be a rotation).
CalibrationFile read_calibration_file(const std::filesystem::path& path);

/// Process CPU seconds of each step of `intrinsics` (printed; the default run must cost no more
/// than OpenCV's calibration sample, bench/calib/calib_cpu_bench).
struct IntrinsicsCpu {
  double startup_s = 0;           ///< before the images: loader, initialisers, options
  double detection_s = 0;         ///< images + detection + cornerSubPix, larger check included
  double larger_check_s = 0;      ///< the larger-board check, part of detection_s:
  double larger_probe_s = 0;      ///<   the probe beyond the edges, every view
  double larger_confirm_s = 0;    ///<   SB's confirmation, views where the checker goes on
  int larger_confirmations = 0;   ///<   how many views needed it
  double calibration_s = 0;       ///< calibrateCamera + per-view residuals
  double sigma_s = 0;             ///< the parameters' σ (intrinsics_std_dev)
  double cross_validation_s = 0;  ///< the two half-set calibrations
  double coverage_s = 0;          ///< coverage and warnings
};

struct IntrinsicsReport {
  IntrinsicsResult result;
  Board board;
  std::string model_name;
  Coverage coverage;
  CrossValidation cross_validation;
  std::vector<Warning> warnings;
  IntrinsicsCpu cpu;
};

/// The YAML text of an intrinsics calibration.
std::string intrinsics_yaml(const IntrinsicsReport& report);

struct PoseReport {
  core::Pinhole pinhole;
  core::Pose camera_pose;  ///< T_world_cam
  double reprojection_rms_px = 0.0;
  std::string cue;  ///< how the board's symmetric ambiguity was resolved
  std::string intrinsics_file, image_file;
  Board board;
  core::Pose board_pose;  ///< T_world_board as given
};

/// The YAML text of a pose calibration: the intrinsics it used plus camera_pose_R/_t.
std::string pose_yaml(const PoseReport& report);

/// The YAML text of one camera of a stereo calibration: its intrinsics (OpenCV's convention in the
/// file) and camera_pose_R/_t (T_world_cam; the rig's left camera is the world origin), with the
/// stereo figures for reference.
std::string stereo_camera_yaml(const core::Pinhole& pinhole, const core::Pose& T_world_cam,
                               const std::string& role, int pairs, double stereo_rms_px,
                               double epipolar_px, double row_rms_px);

/// ROS camera_info YAML (camera_calibration_parsers' format) for an intrinsics result.
std::string ros_camera_info_yaml(const IntrinsicsResult& r, const std::string& camera_name);

}  // namespace hd::calib
