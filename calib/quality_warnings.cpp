#include "calib/quality_warnings.h"

#include <cmath>
#include <cstdio>

namespace hd::calib {

namespace {
std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b, c, d);
  return buf;
}
}  // namespace

std::vector<Warning> quality_warnings(const IntrinsicsResult& r, const Coverage& c,
                                      const CrossValidation& xv) {
  std::vector<Warning> w;
  const double w_px = r.image_size.width, h_px = r.image_size.height;
  const double side = std::max(w_px, h_px);
  const double diag = std::hypot(w_px, h_px);
  const double off = std::hypot(r.cx() - w_px / 2, r.cy() - h_px / 2);
  const double s_cx = r.sigma(2), s_cy = r.sigma(3);
  if (std::max(s_cx, s_cy) > 0.01 * side || (off > 0.10 * diag && c.hull_fraction < 0.60)) {
    w.push_back({"principal_point",
                 fmt("principal point poorly determined: (%.1f, %.1f) px +- (%.1f, %.1f) px",
                     r.cx(), r.cy(), s_cx, s_cy) +
                     fmt(", %.0f px from the image centre, corners cover %.0f%% of the image; add "
                         "views with the board near the image edges and corners",
                         off, 100 * c.hull_fraction)});
  }
  static const char* names[] = {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
  for (int i = 0; i < r.distortion.cols && i < 8; ++i) {
    const double v = r.distortion.at<double>(0, i), s = r.sigma(4 + i);
    if (s > std::max(std::abs(v), 0.1))
      w.push_back({"distortion", std::string("distortion poorly determined: ") + names[i] +
                                     fmt(" = %.3g +- %.3g; add views with the board near the "
                                         "image corners or use a simpler --model (e.g. fix-k3)",
                                         v, s)});
  }
  if (c.grid_fraction < 0.5)
    w.push_back({"coverage", fmt("corners cover only %.0f%% of the 8x6 image grid; move the board "
                                 "into the empty areas (see the report picture)",
                                 100 * c.grid_fraction)});
  if (xv.computed && xv.covered_max_px > 1.0)
    w.push_back({"cross_validation",
                 fmt("calibrations from the two halves of the views disagree by up to %.2f px "
                     "(RMS %.2f px) inside the area the corners cover (%.1f px at worst over the "
                     "whole image): the views do not pin the model down",
                     xv.covered_max_px, xv.covered_rms_px, xv.max_px)});
  if (r.views.size() < 10)
    w.push_back({"few_views", fmt("only %.0f views; 10-20 varied views are recommended",
                                  static_cast<double>(r.views.size()))});
  for (const auto& v : r.views)
    if (v.outlier)
      w.push_back({"outlier_view", v.name + fmt(": reprojection RMS %.2f px is an outlier; check "
                                                "for blur or a mis-detected board",
                                                v.rms_px)});
  return w;
}

}  // namespace hd::calib
