#include "calib/synthetic_views.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace hd::calib {

namespace {
cv::Matx33d rot(double ax, double ay, double az) {
  cv::Matx33d R;
  cv::Rodrigues(cv::Vec3d(0, 0, az), R);
  cv::Matx33d Ry, Rx;
  cv::Rodrigues(cv::Vec3d(0, ay, 0), Ry);
  cv::Rodrigues(cv::Vec3d(ax, 0, 0), Rx);
  return R * Ry * Rx;
}
}  // namespace

std::vector<cv::Point2f> project_corners(const SyntheticCamera& cam, const Board& board,
                                         const BoardPose& pose) {
  std::vector<cv::Point2f> out;
  cv::projectPoints(board.object_points(), pose.rvec, pose.tvec, cam.K, cam.D, out);
  return out;
}

BoardPose random_board_pose(const SyntheticCamera& cam, const Board& board, std::mt19937& rng,
                            double max_tilt_deg) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double s = board.square_m;
  const double bw = (board.cols + 1) * s, bh = (board.rows + 1) * s;
  const cv::Vec3d centre_local((board.cols - 1) * s / 2, (board.rows - 1) * s / 2, 0);
  const double tilt = max_tilt_deg * CV_PI / 180;
  for (int attempt = 0;; ++attempt) {
    const double frac = 0.3 + 0.4 * u01(rng);
    const double Z = cam.K(0, 0) * bw / (frac * cam.size.width);
    const double px = cam.size.width * (0.15 + 0.7 * u01(rng));
    const double py = cam.size.height * (0.15 + 0.7 * u01(rng));
    const cv::Vec3d c((px - cam.K(0, 2)) / cam.K(0, 0) * Z, (py - cam.K(1, 2)) / cam.K(1, 1) * Z,
                      Z);
    // Drawn in a fixed order (function arguments are unsequenced, and GCC and clang differ):
    // the last angle first, as GCC drew them when the tests' figures were taken.
    const double angle_z = (CV_PI / 6) * (2 * u01(rng) - 1);
    const double angle_y = tilt * (2 * u01(rng) - 1);
    const double angle_x = tilt * (2 * u01(rng) - 1);
    const cv::Matx33d R = rot(angle_x, angle_y, angle_z);
    BoardPose p;
    cv::Rodrigues(R, p.rvec);
    p.tvec = c - R * centre_local;
    // Whole board including the margin square must be inside the image.
    std::vector<cv::Point3f> outline = {{static_cast<float>(-s), static_cast<float>(-s), 0},
                                        {static_cast<float>(bw - s), static_cast<float>(-s), 0},
                                        {static_cast<float>(bw - s), static_cast<float>(bh - s), 0},
                                        {static_cast<float>(-s), static_cast<float>(bh - s), 0}};
    std::vector<cv::Point2f> img;
    cv::projectPoints(outline, p.rvec, p.tvec, cam.K, cam.D, img);
    bool inside = true;
    for (const auto& q : img)
      inside =
          inside && q.x > 2 && q.y > 2 && q.x < cam.size.width - 2 && q.y < cam.size.height - 2;
    if (inside || attempt > 1000) return p;
  }
}

SyntheticRenderer::SyntheticRenderer(const SyntheticCamera& cam, int supersample)
    : cam_(cam), ss_(supersample) {
  const int W = cam.size.width * ss_, H = cam.size.height * ss_;
  std::vector<cv::Point2f> px;
  px.reserve(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      // Sample centres; pixel (i, j) spans [i, i+1] in continuous coordinates, OpenCV's corner
      // coordinates put pixel centres at integers, so subtract 0.5.
      px.emplace_back(static_cast<float>((x + 0.5) / ss_ - 0.5),
                      static_cast<float>((y + 0.5) / ss_ - 0.5));
  std::vector<cv::Point2f> und;
  cv::undistortPoints(px, und, cam.K, cam.D, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 1e-12));
  rays_ = cv::Mat(und, true).reshape(2, H);
}

cv::Mat SyntheticRenderer::render(const Board& board, const BoardPose& pose, double blur_sigma_px,
                                  double noise_sigma, std::mt19937& rng) const {
  cv::Matx33d R;
  cv::Rodrigues(pose.rvec, R);
  // Plane z = 0 of the board: camera ray (x, y, 1) ~ H (u, v, 1) with H = [r1 r2 t].
  const cv::Matx33d Hm(R(0, 0), R(0, 1), pose.tvec[0], R(1, 0), R(1, 1), pose.tvec[1], R(2, 0),
                       R(2, 1), pose.tvec[2]);
  const cv::Matx33d Hinv = Hm.inv();
  const double s = board.square_m;
  cv::Mat fine(rays_.rows, rays_.cols, CV_32F);
  for (int y = 0; y < rays_.rows; ++y) {
    const auto* r = rays_.ptr<cv::Vec2f>(y);
    float* o = fine.ptr<float>(y);
    for (int x = 0; x < rays_.cols; ++x) {
      const cv::Vec3d b = Hinv * cv::Vec3d(r[x][0], r[x][1], 1.0);
      float v = 128.f;
      if (b[2] > 0) {
        const double u = b[0] / b[2] / s, w = b[1] / b[2] / s;
        const double fu = std::floor(u), fw = std::floor(w);
        if (fu >= -1 && fu <= board.cols - 1 && fw >= -1 && fw <= board.rows - 1)
          v = (static_cast<long>(fu + fw) & 1) == 0 ? 30.f : 225.f;
        else if (fu >= -2 && fu <= board.cols && fw >= -2 && fw <= board.rows)
          v = 225.f;  // white margin around the squares, like a printed board
      }
      o[x] = v;
    }
  }
  cv::Mat img;
  cv::resize(fine, img, cam_.size, 0, 0, cv::INTER_AREA);  // box filter = supersampled average
  if (blur_sigma_px > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), blur_sigma_px);
  if (noise_sigma > 0) {
    std::normal_distribution<float> n(0.f, static_cast<float>(noise_sigma));
    for (int y = 0; y < img.rows; ++y) {
      float* p = img.ptr<float>(y);
      for (int x = 0; x < img.cols; ++x) p[x] += n(rng);
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8U);
  return out;
}

}  // namespace hd::calib
