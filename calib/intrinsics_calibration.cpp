#include "calib/intrinsics_calibration.h"

#include "calib/intrinsics_uncertainty.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace hd::calib {

std::vector<bool> outlier_views(const std::vector<double>& rms) {
  std::vector<bool> out(rms.size(), false);
  if (rms.empty()) return out;
  std::vector<double> sorted = rms;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t n = sorted.size();
  const double median = n % 2 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  const double mean = std::accumulate(rms.begin(), rms.end(), 0.0) / static_cast<double>(n);
  double var = 0;
  for (double x : rms) var += (x - mean) * (x - mean);
  const double sd = std::sqrt(var / static_cast<double>(n));
  for (std::size_t i = 0; i < n; ++i)
    out[i] =
        (rms[i] > 2.0 * median || rms[i] > mean + 3.0 * sd) && rms[i] > median + kOutlierFloorPx;
  return out;
}

IntrinsicsResult calibrate_intrinsics(const std::vector<View>& views, const Board& board,
                                      cv::Size image_size, const DistortionModel& model,
                                      const IntrinsicsResult* start, bool with_sigma) {
  if (views.size() < 3)
    throw std::runtime_error("calibration needs at least 3 views with the board found, got " +
                             std::to_string(views.size()));
  const auto obj = board.object_points();
  std::vector<std::vector<cv::Point3f>> object_points(views.size(), obj);
  std::vector<std::vector<cv::Point2f>> image_points;
  for (const auto& v : views) image_points.push_back(v.corners);

  IntrinsicsResult r;
  r.image_size = image_size;
  r.flags = model.cv_flags();
  cv::Mat K = cv::Mat::eye(3, 3, CV_64F);  // aspect 1 is the start (and the fixed value) of fx/fy
  cv::Mat D;
  // LU instead of SVD for the normal equations and the sample's 30 iterations: the same minimum
  // on well-posed sets at about half the CPU (bench/calib/calib_cpu_bench, docs/calibration.md).
  int flags = r.flags | cv::CALIB_USE_LU;
  if (start) {
    K = cv::Mat(start->camera_matrix).clone();
    D = start->distortion.clone();
    flags |= cv::CALIB_USE_INTRINSIC_GUESS;
  }
  std::vector<cv::Mat> rvecs, tvecs;
  // The plain overload: no sigma (calibrateCameraExtended inverts the whole (4 + N + 6 * views)
  // normal matrix by SVD for it, ~5 ms here); intrinsics_std_dev gives the same figures cheaper.
  cv::calibrateCamera(
      object_points, image_points, image_size, K, D, rvecs, tvecs, flags,
      cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, DBL_EPSILON));
  r.camera_matrix = cv::Matx33d(K);
  const int n_dist = model.terms == DistortionModel::Terms::rational8 ? 8 : 5;
  r.distortion = D.reshape(1, 1).colRange(0, n_dist).clone();

  // Residuals at the solution, in double (the RMS calibrateCameraExtended returns).
  std::vector<cv::Point3d> obj_d;
  for (const auto& p : obj) obj_d.emplace_back(p.x, p.y, p.z);
  double total2 = 0;
  std::vector<double> rms;
  for (std::size_t i = 0; i < views.size(); ++i) {
    ViewResult vr;
    vr.name = views[i].name;
    vr.rvec = cv::Vec3d(rvecs[i]);
    vr.tvec = cv::Vec3d(tvecs[i]);
    std::vector<cv::Point2d> proj;
    cv::projectPoints(obj_d, rvecs[i], tvecs[i], K, D, proj);
    double sum = 0;
    for (std::size_t j = 0; j < proj.size(); ++j) {
      const cv::Point2d e = cv::Point2d(views[i].corners[j]) - proj[j];
      vr.residuals_px.emplace_back(e);
      sum += e.dot(e);
    }
    total2 += sum;
    vr.rms_px = std::sqrt(sum / static_cast<double>(proj.size()));
    rms.push_back(vr.rms_px);
    r.views.push_back(std::move(vr));
  }
  const std::vector<bool> out = outlier_views(rms);
  for (std::size_t i = 0; i < r.views.size(); ++i) r.views[i].outlier = out[i];
  r.worst_view = static_cast<int>(std::max_element(rms.begin(), rms.end()) - rms.begin());
  r.rms_px = std::sqrt(total2 / static_cast<double>(obj.size() * views.size()));
  if (with_sigma) r.std_dev_intrinsics = intrinsics_std_dev(views, board, r);
  return r;
}

}  // namespace hd::calib
