#include "calib/cross_validation.h"

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace hd::calib {

CrossValidation compare_models(const cv::Matx33d& K_a, const cv::Mat& D_a, const cv::Matx33d& K_b,
                               const cv::Mat& D_b, cv::Size image_size,
                               const std::vector<cv::Point2f>& covered_hull, int grid_cols,
                               int grid_rows) {
  std::vector<cv::Point2f> pixels;
  for (int r = 0; r < grid_rows; ++r)
    for (int c = 0; c < grid_cols; ++c)
      pixels.emplace_back(static_cast<float>((c + 0.5) * image_size.width / grid_cols),
                          static_cast<float>((r + 0.5) * image_size.height / grid_rows));
  auto unproject = [&](const cv::Matx33d& K, const cv::Mat& D) {
    std::vector<cv::Point2f> n;
    cv::undistortPoints(
        pixels, n, K, D, cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-9));
    std::vector<Eigen::Vector3d> rays;
    for (const auto& p : n) rays.push_back(Eigen::Vector3d(p.x, p.y, 1.0).normalized());
    return rays;
  };
  const auto rays_a = unproject(K_a, D_a), rays_b = unproject(K_b, D_b);
  std::vector<bool> covered(pixels.size(), true);
  if (!covered_hull.empty())
    for (std::size_t i = 0; i < pixels.size(); ++i)
      covered[i] = cv::pointPolygonTest(covered_hull, pixels[i], false) >= 0;
  // Two calibrations may differ by a camera rotation that their extrinsics absorb (a shift of cx
  // trades against a pan): that is not a disagreement. Remove the best rotation (Kabsch, over the
  // covered grid points) before comparing, as mrcal's projection-difference does.
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < pixels.size(); ++i)
    if (covered[i]) H += rays_a[i] * rays_b[i].transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  S(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R = svd.matrixV() * S * svd.matrixU().transpose();
  std::vector<cv::Point3f> rotated;
  for (const auto& r : rays_a) {
    const Eigen::Vector3d q = R * r;
    rotated.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()),
                         static_cast<float>(q.z()));
  }
  std::vector<cv::Point2f> reproj;
  cv::projectPoints(rotated, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K_b, D_b, reproj);
  CrossValidation cv;
  cv.computed = true;
  double sum = 0, sum_cov = 0;
  int n_cov = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    const double e = cv::norm(reproj[i] - pixels[i]);
    sum += e * e;
    cv.max_px = std::max(cv.max_px, e);
    if (covered[i]) {
      sum_cov += e * e;
      ++n_cov;
      cv.covered_max_px = std::max(cv.covered_max_px, e);
    }
  }
  cv.rms_px = std::sqrt(sum / static_cast<double>(pixels.size()));
  cv.covered_rms_px = n_cov ? std::sqrt(sum_cov / n_cov) : 0.0;
  return cv;
}

CrossValidation cross_validate(const std::vector<View>& views, const Board& board,
                               cv::Size image_size, const DistortionModel& model,
                               const IntrinsicsResult* start) {
  if (views.size() < 6) return {};
  std::vector<View> a, b;
  for (std::size_t i = 0; i < views.size(); ++i) (i % 2 ? b : a).push_back(views[i]);
  const auto ra = calibrate_intrinsics(a, board, image_size, model, start);
  const auto rb = calibrate_intrinsics(b, board, image_size, model, start);
  std::vector<cv::Point2f> all, hull;
  for (const auto& v : views) all.insert(all.end(), v.corners.begin(), v.corners.end());
  cv::convexHull(all, hull);
  auto cv = compare_models(ra.camera_matrix, ra.distortion, rb.camera_matrix, rb.distortion,
                           image_size, hull);
  cv.views_a = static_cast<int>(a.size());
  cv.views_b = static_cast<int>(b.size());
  return cv;
}

}  // namespace hd::calib
