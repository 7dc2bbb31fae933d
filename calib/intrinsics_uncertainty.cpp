#include "calib/intrinsics_uncertainty.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace hd::calib {

namespace {

// Which of fx fy cx cy k1 k2 p1 p2 k3 [k4 k5 k6] calibrateCamera estimated (its parameter mask).
std::vector<bool> free_intrinsics(int flags, int n_dist) {
  std::vector<bool> f(static_cast<std::size_t>(4 + n_dist), true);
  if (flags & (cv::CALIB_FIX_ASPECT_RATIO | cv::CALIB_FIX_FOCAL_LENGTH)) f[0] = false;
  if (flags & cv::CALIB_FIX_FOCAL_LENGTH) f[1] = false;
  if (flags & cv::CALIB_FIX_PRINCIPAL_POINT) f[2] = f[3] = false;
  const int fixed_k[] = {
      cv::CALIB_FIX_K1, cv::CALIB_FIX_K2, 0, 0, cv::CALIB_FIX_K3, cv::CALIB_FIX_K4,
      cv::CALIB_FIX_K5, cv::CALIB_FIX_K6};
  for (int i = 0; i < n_dist; ++i)
    if (fixed_k[i] && (flags & fixed_k[i])) f[static_cast<std::size_t>(4 + i)] = false;
  if (flags & (cv::CALIB_ZERO_TANGENT_DIST | cv::CALIB_FIX_TANGENT_DIST)) f[6] = f[7] = false;
  if (n_dist > 5 && !(flags & cv::CALIB_RATIONAL_MODEL))
    for (int i = 5; i < n_dist; ++i) f[static_cast<std::size_t>(4 + i)] = false;
  return f;
}

}  // namespace

cv::Mat intrinsics_std_dev(const std::vector<View>& views, const Board& board,
                           const IntrinsicsResult& r) {
  const int n_dist = r.distortion.cols;
  const int n_all = 4 + n_dist;
  const std::vector<bool> free = free_intrinsics(r.flags, n_dist);
  std::vector<int> cols;  // Jacobian column of each free intrinsic
  for (int i = 0; i < n_all; ++i)
    if (free[static_cast<std::size_t>(i)]) cols.push_back(i);
  const int ni = static_cast<int>(cols.size());
  const bool fix_aspect = r.flags & cv::CALIB_FIX_ASPECT_RATIO;
  const double aspect = r.fx() / r.fy();
  if (views.size() != r.views.size()) throw std::logic_error("intrinsics_std_dev: views differ");

  std::vector<cv::Point3d> obj;
  for (const auto& p : board.object_points()) obj.emplace_back(p.x, p.y, p.z);
  const cv::Mat K(r.camera_matrix);
  cv::Mat S = cv::Mat::zeros(ni, ni, CV_64F);  // Schur complement of the pose blocks
  double err2 = 0;
  int residuals = 0;
  std::vector<cv::Point2d> proj;
  cv::Mat J, Ji(2 * static_cast<int>(obj.size()), ni, CV_64F), Cinv;
  for (std::size_t v = 0; v < views.size(); ++v) {
    // Columns: rotation 3, translation 3, fx fy, cx cy, distortion (OpenCV's order).
    cv::projectPoints(obj, r.views[v].rvec, r.views[v].tvec, K, r.distortion, proj, J);
    for (std::size_t k = 0; k < proj.size(); ++k) {
      const cv::Point2d e = cv::Point2d(views[v].corners[k]) - proj[k];
      err2 += e.dot(e);
    }
    residuals += 2 * static_cast<int>(proj.size());
    for (int j = 0; j < ni; ++j) J.col(6 + cols[static_cast<std::size_t>(j)]).copyTo(Ji.col(j));
    // fx = aspect * fy: fy's column carries fx's too, as calibrateCamera's does.
    if (fix_aspect && free[1]) {
      const int fy_col = free[0] ? 1 : 0;
      Ji.col(fy_col) += aspect * J.col(6);
    }
    const cv::Mat Je = J.colRange(0, 6);
    const cv::Mat B = Ji.t() * Je;  // ni x 6
    cv::invert(Je.t() * Je, Cinv, cv::DECOMP_CHOLESKY);
    S += Ji.t() * Ji - B * Cinv * B.t();
  }
  // OpenCV 4.6's denominator, corners - free parameters, so the figures stay those the tests and
  // the README were checked against; OpenCV >= 4.8 uses 2 * corners - free (sigma ~1.4x smaller).
  const int n_free = ni + 6 * static_cast<int>(views.size());
  const double sigma2 = err2 / static_cast<double>(residuals / 2 - n_free);
  cv::Mat Sinv;
  cv::invert(S, Sinv, cv::DECOMP_SVD);
  cv::Mat out = cv::Mat::zeros(1, n_all, CV_64F);
  for (int j = 0; j < ni; ++j)
    out.at<double>(0, cols[static_cast<std::size_t>(j)]) =
        std::sqrt(Sinv.at<double>(j, j) * sigma2);
  if (fix_aspect) out.at<double>(0, 0) = out.at<double>(0, 1);
  return out;
}

}  // namespace hd::calib
