// hybrid-bench-calib: accuracy vs time of the calibration pipeline on synthetic views of a known
// camera, next to OpenCV's plain pipeline (findChessboardCorners + calibrateCamera, default flags)
// on the same images in the same run.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <opencv2/calib3d.hpp>

#include "calib/corner_detector.h"
#include "calib/intrinsics_calibration.h"
#include "calib/synthetic_views.h"

using namespace hd::calib;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Setting {
  const char* name;
  bool plain;  // OpenCV's plain pipeline
  DetectorOptions opt;
};

// Detections re-ordered to the truth's numbering (a benchmark knows it), so poses compare.
bool align(std::vector<cv::Point2f>& det, const std::vector<cv::Point2f>& truth) {
  double fwd = 0, rev = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    fwd += cv::norm(det[i] - truth[i]);
    rev += cv::norm(det[truth.size() - 1 - i] - truth[i]);
  }
  if (rev < fwd) std::reverse(det.begin(), det.end());
  return std::min(fwd, rev) / static_cast<double>(truth.size()) < 5.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hybrid-bench-calib: accuracy against time of the calibration pipeline on synthetic views "
      "of a known camera, beside OpenCV's plain pipeline on the same images"};
  CLI11_PARSE(app, argc, argv);
  SyntheticCamera cam;
  cam.size = {640, 480};
  cam.K = cv::Matx33d(600, 0, 330, 0, 602, 236, 0, 0, 1);
  cam.D = (cv::Mat_<double>(1, 5) << -0.25, 0.1, 0.001, -0.0005, 0.0);
  const Board board = Board::parse("9x6", 0.025);
  const int max_views = 40;
  std::mt19937 rng(42);
  SyntheticRenderer renderer(cam, 3);
  std::vector<BoardPose> poses;
  std::vector<cv::Mat> images;
  std::vector<std::vector<cv::Point2f>> truth;
  for (int i = 0; i < max_views; ++i) {
    poses.push_back(random_board_pose(cam, board, rng));
    images.push_back(renderer.render(board, poses.back(), 0.8, 3.0, rng));  // blur 0.8 px, noise 3
    truth.push_back(project_corners(cam, board, poses.back()));
  }
  std::printf(
      "camera 640x480 fx 600 fy 602 cx 330 cy 236 k1 -0.25 k2 0.1; board 9x6; render 3x3 "
      "supersampled, blur sigma 0.8 px, noise sigma 3 grey levels\n");
  std::printf("%-22s %5s %6s %9s %9s %9s %9s %9s %10s %10s\n", "pipeline", "views", "found",
              "corner px", "|dfx| px", "|dcx| px", "|dk1|", "rot deg", "trans mm", "time s");
  std::vector<Setting> settings;
  auto mk = [](bool classic, bool sb, Refinement r) {
    DetectorOptions o;
    o.use_classic = classic;
    o.use_sb_fallback = sb;
    o.refinement = r;
    o.check_larger = false;
    return o;
  };
  settings.push_back({"opencv plain", true, {}});
  settings.push_back({"classic, no subpix", false, mk(true, false, Refinement::kNone)});
  settings.push_back({"classic + subpix 5", false, mk(true, false, Refinement::kSubPix5)});
  settings.push_back({"classic + subpix 11", false, mk(true, false, Refinement::kSubPix11)});
  settings.push_back({"SB only", false, mk(false, true, Refinement::kNone)});
  for (const auto& s : settings) {
    std::vector<std::vector<cv::Point2f>> det(max_views);
    std::vector<double> det_time(max_views, 0.0);
    std::vector<bool> ok(max_views, false);
    for (int i = 0; i < max_views; ++i) {
      const double t0 = now_s();
      if (s.plain) {
        ok[i] = cv::findChessboardCorners(images[i], board.pattern(), det[i]);
      } else {
        const Detection d = detect_corners(images[i], board, s.opt);
        ok[i] = d.found();
        det[i] = d.corners;
      }
      det_time[i] = now_s() - t0;
      if (ok[i]) ok[i] = align(det[i], truth[i]);
    }
    for (int n : {5, 10, 20, 40}) {
      std::vector<View> views;
      std::vector<int> idx;
      double t = 0, corner_sq = 0;
      int corners = 0;
      for (int i = 0; i < n; ++i) {
        t += det_time[i];
        if (!ok[i]) continue;
        views.push_back({std::to_string(i), det[i]});
        idx.push_back(i);
        for (std::size_t j = 0; j < det[i].size(); ++j) {
          const cv::Point2f e = det[i][j] - truth[i][j];
          corner_sq += e.dot(e);
          ++corners;
        }
      }
      if (views.size() < 3) {
        std::printf("%-22s %5d %6zu   (too few boards found)\n", s.name, n, views.size());
        continue;
      }
      const double t0 = now_s();
      double fx, cx, k1;
      std::vector<cv::Vec3d> rv, tv;
      if (s.plain) {
        std::vector<std::vector<cv::Point3f>> obj(views.size(), board.object_points());
        std::vector<std::vector<cv::Point2f>> img;
        for (auto& v : views) img.push_back(v.corners);
        cv::Mat K, D;
        std::vector<cv::Mat> r, tt;
        cv::calibrateCamera(obj, img, cam.size, K, D, r, tt);
        fx = K.at<double>(0, 0);
        cx = K.at<double>(0, 2);
        k1 = D.at<double>(0);
        for (std::size_t i = 0; i < r.size(); ++i) {
          rv.emplace_back(r[i]);
          tv.emplace_back(tt[i]);
        }
      } else {
        const auto res = calibrate_intrinsics(views, board, cam.size, DistortionModel{});
        fx = res.fx();
        cx = res.cx();
        k1 = res.distortion.at<double>(0, 0);
        for (const auto& v : res.views) {
          rv.push_back(v.rvec);
          tv.push_back(v.tvec);
        }
      }
      t += now_s() - t0;
      double rot = 0, trans = 0;
      for (std::size_t i = 0; i < idx.size(); ++i) {
        cv::Matx33d Ra, Rb;
        cv::Rodrigues(rv[i], Ra);
        cv::Rodrigues(poses[static_cast<std::size_t>(idx[i])].rvec, Rb);
        cv::Vec3d dr;
        cv::Rodrigues(Ra * Rb.t(), dr);
        rot += cv::norm(dr) * 180 / CV_PI;
        trans += cv::norm(tv[i] - poses[static_cast<std::size_t>(idx[i])].tvec) * 1000;
      }
      std::printf("%-22s %5d %6zu %9.3f %9.3f %9.3f %9.4f %9.3f %10.2f %10.3f\n", s.name, n,
                  views.size(), std::sqrt(corner_sq / corners), std::abs(fx - 600),
                  std::abs(cx - 330), std::abs(k1 + 0.25), rot / idx.size(), trans / idx.size(), t);
    }
  }
  std::printf(
      "corner px: RMS distance of the detected corners to the true projections; rot/trans: "
      "mean pose error per view; time: detection of those views + calibration, this run\n");
  return 0;
}
