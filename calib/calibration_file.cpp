#include "calib/calibration_file.h"

#include <cmath>
#include <ctime>
#include <opencv2/core.hpp>
#include <sstream>

#include "core/opencv_pixels.h"

namespace hd::calib {

namespace {

std::string now_utc() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

[[noreturn]] void fail(const std::filesystem::path& p, const std::string& key,
                       const std::string& what) {
  throw CalibrationFileError(p.string() + ": key '" + key + "': " + what);
}

cv::Mat read_matrix(const cv::FileStorage& fs, const std::filesystem::path& p,
                    const std::string& key, bool required) {
  const cv::FileNode n = fs[key];
  if (n.empty()) {
    if (required) fail(p, key, "missing");
    return {};
  }
  cv::Mat m;
  try {
    n >> m;
  } catch (const cv::Exception&) {
    fail(p, key, "not an OpenCV matrix (!!opencv-matrix with rows, cols, dt, data)");
  }
  if (m.empty()) fail(p, key, "not an OpenCV matrix (!!opencv-matrix with rows, cols, dt, data)");
  m.convertTo(m, CV_64F);
  for (auto it = m.begin<double>(); it != m.end<double>(); ++it)
    if (!std::isfinite(*it)) fail(p, key, "holds a non-finite number");
  return m;
}

int read_int(const cv::FileStorage& fs, const std::filesystem::path& p, const std::string& key) {
  const cv::FileNode n = fs[key];
  if (n.empty()) fail(p, key, "missing");
  if (!n.isInt()) fail(p, key, "expected an integer");
  return static_cast<int>(n);
}

cv::Mat pose_R(const core::Pose& pose) {
  cv::Mat R(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.at<double>(i, j) = pose.R(i, j);
  return R;
}
cv::Mat pose_t(const core::Pose& pose) {
  return (cv::Mat_<double>(3, 1) << pose.t.x(), pose.t.y(), pose.t.z());
}

// The file holds OpenCV's numbers (pixel centres at integers); core::to_opencv converts.
void write_pinhole(cv::FileStorage& fs, const core::Pinhole& pinhole) {
  const core::OpenCvIntrinsics p = core::to_opencv(pinhole);
  fs << "image_width" << p.width << "image_height" << p.height;
  fs << "camera_matrix" << cv::Mat(cv::Matx33d(p.fx, 0, p.cx, 0, p.fy, p.cy, 0, 0, 1));
  cv::Mat d(p.distortion_count, 1, CV_64F);
  for (int i = 0; i < p.distortion_count; ++i) d.at<double>(i) = p.distortion[i];
  fs << "distortion_coefficients" << d;
}

}  // namespace

CalibrationFile read_calibration_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw CalibrationFileError(path.string() + ": no such calibration file");
  cv::FileStorage fs;
  try {
    fs.open(path.string(), cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& e) {
    throw CalibrationFileError(path.string() + ": not a readable OpenCV FileStorage YAML file (" +
                               e.err + ")");
  }
  if (!fs.isOpened())
    throw CalibrationFileError(path.string() + ": not a readable OpenCV FileStorage YAML file");
  CalibrationFile out;
  // The file's numbers are OpenCV's; they become a core::Pinhole once, at the end (from_opencv).
  core::OpenCvIntrinsics ph;
  ph.width = read_int(fs, path, "image_width");
  ph.height = read_int(fs, path, "image_height");
  if (ph.width <= 0 || ph.height <= 0 || ph.width > 100000 || ph.height > 100000)
    fail(path, "image_width/image_height", "expected a positive image size");
  const cv::Mat K = read_matrix(fs, path, "camera_matrix", true);
  if (K.rows != 3 || K.cols != 3) fail(path, "camera_matrix", "expected a 3x3 matrix");
  ph.fx = K.at<double>(0, 0);
  ph.fy = K.at<double>(1, 1);
  ph.cx = K.at<double>(0, 2);
  ph.cy = K.at<double>(1, 2);
  if (ph.fx <= 0 || ph.fy <= 0) fail(path, "camera_matrix", "focal lengths must be positive");
  const cv::Mat D = read_matrix(fs, path, "distortion_coefficients", true);
  const int nd = static_cast<int>(D.total());
  if (nd != 4 && nd != 5 && nd != 8)
    fail(path, "distortion_coefficients",
         "expected 4, 5 or 8 coefficients, got " + std::to_string(nd));
  ph.distortion_count = nd;
  for (int i = 0; i < nd; ++i) ph.distortion[static_cast<std::size_t>(i)] = D.at<double>(i);
  out.pinhole = core::from_opencv(ph);
  if (const auto n = fs["avg_reprojection_error"]; !n.empty()) {
    if (!n.isReal() && !n.isInt()) fail(path, "avg_reprojection_error", "expected a number");
    out.avg_reprojection_error_px = static_cast<double>(n);
  }
  const cv::Mat R = read_matrix(fs, path, "camera_pose_R", false);
  const cv::Mat t = read_matrix(fs, path, "camera_pose_t", false);
  if (R.empty() != t.empty())
    fail(path, R.empty() ? "camera_pose_R" : "camera_pose_t",
         "missing while the other pose key is present");
  if (!R.empty()) {
    if (R.rows != 3 || R.cols != 3) fail(path, "camera_pose_R", "expected a 3x3 matrix");
    if (t.total() != 3) fail(path, "camera_pose_t", "expected 3 values");
    core::Pose pose;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) pose.R(i, j) = R.at<double>(i, j);
      pose.t(i) = t.at<double>(i);
    }
    if (!pose.valid(1e-4)) fail(path, "camera_pose_R", "not a rotation (orthonormal, det +1)");
    out.camera_pose = pose;
  }
  if (const auto n = fs["warnings"]; n.isSeq())
    for (const auto& w : n) out.warnings.push_back(static_cast<std::string>(w));
  return out;
}

std::string intrinsics_yaml(const IntrinsicsReport& rep) {
  const IntrinsicsResult& r = rep.result;
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "calibration_time" << now_utc();
  fs << "nr_of_frames" << static_cast<int>(r.views.size());
  fs << "image_width" << r.image_size.width << "image_height" << r.image_size.height;
  fs << "board_width" << rep.board.cols << "board_height" << rep.board.rows;
  fs << "square_size" << rep.board.square_m;
  fs << "flags" << r.flags;
  fs << "distortion_model" << rep.model_name;
  fs << "camera_matrix" << cv::Mat(r.camera_matrix);
  fs << "distortion_coefficients" << r.distortion.reshape(1, r.distortion.cols);
  fs << "avg_reprojection_error" << r.rms_px;
  cv::Mat per_view(static_cast<int>(r.views.size()), 1, CV_64F);
  cv::Mat extr(static_cast<int>(r.views.size()), 6, CV_64F);
  for (std::size_t i = 0; i < r.views.size(); ++i) {
    const int row = static_cast<int>(i);
    per_view.at<double>(row) = r.views[i].rms_px;
    for (int k = 0; k < 3; ++k) {
      extr.at<double>(row, k) = r.views[i].rvec[k];
      extr.at<double>(row, 3 + k) = r.views[i].tvec[k];
    }
  }
  fs << "per_view_reprojection_errors" << per_view;
  fs << "extrinsic_parameters" << extr;
  fs << "view_names"
     << "[";
  for (const auto& v : r.views) fs << v.name;
  fs << "]";
  fs << "worst_view" << r.views[static_cast<std::size_t>(r.worst_view)].name;
  fs << "outlier_views"
     << "[";
  for (const auto& v : r.views)
    if (v.outlier) fs << v.name;
  fs << "]";
  fs << "intrinsics_std_dev" << r.std_dev_intrinsics.reshape(1, r.std_dev_intrinsics.cols);
  fs << "cross_validation_px"
     << "{";
  fs << "computed" << static_cast<int>(rep.cross_validation.computed);
  fs << "max" << rep.cross_validation.max_px << "rms" << rep.cross_validation.rms_px;
  fs << "covered_max" << rep.cross_validation.covered_max_px;
  fs << "covered_rms" << rep.cross_validation.covered_rms_px;
  fs << "views_a" << rep.cross_validation.views_a << "views_b" << rep.cross_validation.views_b;
  fs << "}";
  fs << "coverage_hull_fraction" << rep.coverage.hull_fraction;
  fs << "coverage_grid_fraction" << rep.coverage.grid_fraction;
  fs << "coverage_grid" << rep.coverage.occupancy;
  fs << "coverage_board_size_range"
     << cv::Mat(cv::Vec2d(rep.coverage.board_size_min, rep.coverage.board_size_max));
  fs << "coverage_tilt_range_deg"
     << cv::Mat(cv::Vec2d(rep.coverage.tilt_min_deg, rep.coverage.tilt_max_deg));
  fs << "warning_codes"
     << "[";
  for (const auto& w : rep.warnings) fs << w.code;
  fs << "]";
  fs << "warnings"
     << "[";
  for (const auto& w : rep.warnings) fs << w.message;
  fs << "]";
  return fs.releaseAndGetString();
}

std::string pose_yaml(const PoseReport& rep) {
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "calibration_time" << now_utc();
  fs << "intrinsics_file" << rep.intrinsics_file << "pose_image" << rep.image_file;
  fs << "board_width" << rep.board.cols << "board_height" << rep.board.rows;
  fs << "square_size" << rep.board.square_m;
  write_pinhole(fs, rep.pinhole);
  fs << "board_pose_R" << pose_R(rep.board_pose) << "board_pose_t" << pose_t(rep.board_pose);
  fs << "camera_pose_R" << pose_R(rep.camera_pose) << "camera_pose_t" << pose_t(rep.camera_pose);
  fs << "pose_reprojection_error" << rep.reprojection_rms_px;
  fs << "pose_ambiguity_cue" << rep.cue;
  return fs.releaseAndGetString();
}

std::string stereo_camera_yaml(const core::Pinhole& pinhole, const core::Pose& T_world_cam,
                               const std::string& role, int pairs, double stereo_rms_px,
                               double epipolar_px, double row_rms_px) {
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "calibration_time" << now_utc();
  fs << "stereo_role" << role << "nr_of_pairs" << pairs;
  write_pinhole(fs, pinhole);
  fs << "camera_pose_R" << pose_R(T_world_cam) << "camera_pose_t" << pose_t(T_world_cam);
  fs << "stereo_rms_px" << stereo_rms_px << "stereo_epipolar_error_px" << epipolar_px;
  fs << "stereo_rectified_row_rms_px" << row_rms_px;
  return fs.releaseAndGetString();
}

std::string ros_camera_info_yaml(const IntrinsicsResult& r, const std::string& camera_name) {
  std::ostringstream o;
  o.precision(10);
  auto row = [&](const std::vector<double>& v) {
    o << "[";
    for (std::size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
    o << "]\n";
  };
  const auto& K = r.camera_matrix;
  o << "image_width: " << r.image_size.width << "\nimage_height: " << r.image_size.height
    << "\ncamera_name: " << camera_name << "\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: ";
  row({K(0, 0), K(0, 1), K(0, 2), K(1, 0), K(1, 1), K(1, 2), 0, 0, 1});
  const bool rational = r.distortion.cols == 8;
  o << "distortion_model: " << (rational ? "rational_polynomial" : "plumb_bob")
    << "\ndistortion_coefficients:\n  rows: 1\n  cols: " << r.distortion.cols << "\n  data: ";
  std::vector<double> d;
  for (int i = 0; i < r.distortion.cols; ++i) d.push_back(r.distortion.at<double>(0, i));
  row(d);
  o << "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: ";
  row({1, 0, 0, 0, 1, 0, 0, 0, 1});
  o << "projection_matrix:\n  rows: 3\n  cols: 4\n  data: ";
  row({K(0, 0), 0, K(0, 2), 0, 0, K(1, 1), K(1, 2), 0, 0, 0, 1, 0});
  return o.str();
}

}  // namespace hd::calib
