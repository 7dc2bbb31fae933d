// hybrid-fig3: the paper's Fig. 3 -- a top view of the reprojection error E over a 1 m x 1 m area
// (plane y = 0 of the real camera) for d = 0.5 m, real camera 1600x1200, virtual 800x600 moved
// 0.02 m sideways and turned 10 degrees. Writes a PNG and prints E at a few depths next to the
// paper's figures (about 200 px near the camera, 0 at d, about 20 px at 1 m).

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/reprojection_error.h"
#include "core/view_setup.h"

namespace {

using hd::core::Pinhole;
using hd::core::ViewSetup;

Pinhole pinhole(double f, int w, int h) {
  return Pinhole::centred(f, w, h);
}

bool sees(const Pinhole& k, const hd::core::Pose& T, const Eigen::Vector3d& X, double near) {
  const Eigen::Vector3d p = T.to_camera(X);
  if (!(p.z() > near)) return false;
  const Eigen::Vector2d uv = k.project(p);
  return uv.x() >= 0 && uv.x() <= k.width && uv.y() >= 0 && uv.y() <= k.height;
}

/// HSV hue from red (E = 0) through yellow, green, turquoise, blue to violet (E >= e_top), on a
/// log(1 + E) scale like the paper's figure (red at d, turquoise around 20 px, violet ~200 px).
cv::Vec3b colour_of(double e_px, double e_top_px) {
  const double t = std::log1p(std::min(e_px, e_top_px)) / std::log1p(e_top_px);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(static_cast<int>(std::lround(135.0 * t)), 255, 255));
  cv::Mat bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr.at<cv::Vec3b>(0, 0);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hybrid-fig3: top-view map of the reprojection error E (the paper's Fig. 3)"};
  std::string out = "fig3.png";
  int map_px = 800;
  double d_m = 0.5, f_real = 2000, f_virt = 1000, shift_m = 0.02, yaw_deg = 10, e_top = 200;
  app.add_option("--out", out, "PNG file to write")->capture_default_str();
  app.add_option("--size", map_px, "map size in pixels (square, 1 m)")
      ->check(CLI::Range(100, 4000))
      ->capture_default_str();
  app.add_option("--d", d_m, "projection plane distance d [m]")->capture_default_str();
  app.add_option("--f-real", f_real, "real camera focal length [px] (1600x1200)")
      ->capture_default_str();
  app.add_option("--f-virtual", f_virt, "virtual camera focal length [px] (800x600)")
      ->capture_default_str();
  app.add_option("--shift", shift_m, "virtual camera sideways translation [m]")
      ->capture_default_str();
  app.add_option("--yaw", yaw_deg, "virtual camera turn [deg]")->capture_default_str();
  app.add_option("--e-top", e_top, "E at the violet end of the colour scale [px]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  ViewSetup s;
  s.real = pinhole(f_real, 1600, 1200);
  s.virt = pinhole(f_virt, 800, 600);
  s.T_world_virt.R =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  s.T_world_virt.t = {shift_m, 0, 0};
  s.d_m = d_m;
  s.workspace = {{-0.5, -0.5, 0.0}, {0.5, 0.5, 1.0}};
  if (!s.valid()) {
    std::fprintf(stderr, "hybrid-fig3: invalid setup (check --d, --f-real, --f-virtual)\n");
    return 2;
  }

  // Layout: map on the left (x right, depth z up, cameras at the bottom), scale bar on the right.
  const int margin = 60, bar_w = 30, right = 170, top = 50;
  cv::Mat img(map_px + top + margin, map_px + margin + right, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Vec3b outside(200, 200, 200), white(255, 255, 255), inf_black(0, 0, 0);
  for (int r = 0; r < map_px; ++r) {
    const double z = 1.0 - (r + 0.5) / map_px;
    for (int c = 0; c < map_px; ++c) {
      const double x = -0.5 + (c + 0.5) / map_px;
      const Eigen::Vector3d X(x, 0, z);
      cv::Vec3b px = outside;
      if (sees(s.virt, s.T_world_virt, X, s.near_m)) {
        const auto e = hd::core::reprojection_error(s, X);
        if (e) px = std::isfinite(*e) ? colour_of(*e, e_top) : inf_black;
      } else if (sees(s.real, s.T_world_real, X, s.near_m)) {
        px = white;
      }
      img.at<cv::Vec3b>(top + r, margin + c) = px;
    }
  }
  const cv::Scalar black(0, 0, 0);
  cv::rectangle(img, {margin, top}, {margin + map_px, top + map_px}, black, 1);
  auto to_px = [&](double x, double z) {
    return cv::Point(margin + static_cast<int>((x + 0.5) * map_px),
                     top + static_cast<int>((1.0 - z) * map_px));
  };
  cv::circle(img, to_px(0, 0), 5, black, cv::FILLED);
  cv::circle(img, to_px(shift_m, 0), 5, cv::Scalar(180, 0, 180), cv::FILLED);
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  char title[160];
  std::snprintf(title, sizeof title, "E [px], top view, d = %.2f m, virtual: %.3f m, %.0f deg", d_m,
                shift_m, yaw_deg);
  cv::putText(img, title, {margin, 32}, font, 0.6, black, 1, cv::LINE_AA);
  for (int i = 0; i <= 4; ++i) {
    const double v = -0.5 + 0.25 * i;
    char buf[16];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    cv::putText(img, buf, {to_px(v, 0).x - 18, top + map_px + 20}, font, 0.45, black, 1,
                cv::LINE_AA);
    std::snprintf(buf, sizeof buf, "%.2f", 0.25 * i);
    cv::putText(img, buf, {8, to_px(0, 0.25 * i).y + 5}, font, 0.45, black, 1, cv::LINE_AA);
  }
  cv::putText(img, "x [m]", {margin + map_px / 2 - 20, top + map_px + 45}, font, 0.5, black, 1,
              cv::LINE_AA);
  cv::putText(img, "z [m]", {8, top - 8}, font, 0.5, black, 1, cv::LINE_AA);
  // Scale bar: log(1 + E) like the map.
  const int bx = margin + map_px + 30;
  for (int r = 0; r < map_px; ++r) {
    const double t = 1.0 - (r + 0.5) / map_px;
    const double e = std::expm1(t * std::log1p(e_top));
    cv::line(img, {bx, top + r}, {bx + bar_w, top + r}, cv::Scalar(colour_of(e, e_top)), 1);
  }
  cv::rectangle(img, {bx, top}, {bx + bar_w, top + map_px}, black, 1);
  for (double e : {0.0, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0}) {
    if (e > e_top) break;
    const int y = top + static_cast<int>((1.0 - std::log1p(e) / std::log1p(e_top)) * map_px);
    cv::line(img, {bx + bar_w, y}, {bx + bar_w + 6, y}, black, 1);
    char buf[16];
    std::snprintf(buf, sizeof buf, "%g", e);
    cv::putText(img, buf, {bx + bar_w + 10, y + 5}, font, 0.45, black, 1, cv::LINE_AA);
  }
  cv::putText(img, "E [px]", {bx - 5, top - 8}, font, 0.5, black, 1, cv::LINE_AA);
  cv::putText(img, "white: real only", {bx - 10, top + map_px + 20}, font, 0.4, black, 1,
              cv::LINE_AA);
  cv::putText(img, "grey: neither", {bx - 10, top + map_px + 38}, font, 0.4, black, 1, cv::LINE_AA);

  // Write atomically: a reader never sees half a PNG.
  const std::string tmp = out + ".tmp.png";
  if (!cv::imwrite(tmp, img) || std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::remove(tmp.c_str());
    std::fprintf(stderr, "hybrid-fig3: %s: cannot write\n", out.c_str());
    return 1;
  }

  // Figures along the virtual optical axis (E depends mostly on depth here).
  std::printf("hybrid-fig3: wrote %s (%dx%d map, 1 m x 1 m)\n", out.c_str(), map_px, map_px);
  std::printf("focal lengths: real %.0f px (1600x1200), virtual %.0f px (800x600)\n", f_real,
              f_virt);
  std::printf("%-34s %12s %12s\n", "point on the virtual optical axis", "E [px]", "paper");
  const Eigen::Vector3d axis = s.T_world_virt.R.col(2);
  auto at_depth = [&](double z_world) {  // the axis point at world depth z
    const double k = (z_world - s.T_world_virt.t.z()) / axis.z();
    return Eigen::Vector3d(s.T_world_virt.t + k * axis);
  };
  struct Row {
    double z;
    const char* paper;
  };
  for (const Row row : {Row{0.05, ""}, Row{0.08, "~200 (near)"}, Row{0.1, ""}, Row{0.25, ""},
                        Row{d_m, "0 (at d)"}, Row{0.75, ""}, Row{1.0, "~20 (at 1 m)"}}) {
    const auto e = hd::core::reprojection_error(s, at_depth(row.z));
    char label[64];
    std::snprintf(label, sizeof label, "z = %.2f m", row.z);
    if (e && std::isfinite(*e))
      std::printf("%-34s %12.2f %12s\n", label, *e, row.paper);
    else
      std::printf("%-34s %12s %12s\n", label, e ? "inf" : "undefined", row.paper);
  }
  return 0;
}
