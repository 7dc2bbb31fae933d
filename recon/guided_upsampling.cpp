#include "recon/guided_upsampling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/utility.hpp>
#include <stdexcept>

namespace hd::recon {

namespace {

template <int CN>
int colour_distance(const uint8_t* a, const uint8_t* b) {
  int d = 0;
  for (int k = 0; k < CN; ++k) {
    const int t = int(a[k]) - int(b[k]);
    d += t * t;
  }
  return d;
}

template <int CN>
void upsample_rows(const cv::Mat& coarse, const cv::Mat& cg, const cv::Mat& fg, double sx,
                   double sy, float agree, cv::Mat& out, int row_begin, int row_end) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const int cw = coarse.cols, ch = coarse.rows;
  const float inv_sx = static_cast<float>(1.0 / sx), inv_sy = static_cast<float>(1.0 / sy);
  const float to_full = static_cast<float>(sx);
  for (int y = row_begin; y < row_end; ++y) {
    const float yc = (y + 0.5f) * inv_sy - 0.5f;
    const int y0 = static_cast<int>(std::floor(yc));
    const float fy = yc - y0;
    const int ya = std::clamp(y0, 0, ch - 1), yb = std::clamp(y0 + 1, 0, ch - 1);
    const float* c0 = coarse.ptr<float>(ya);
    const float* c1 = coarse.ptr<float>(yb);
    const uint8_t* g0 = cg.ptr<uint8_t>(ya);
    const uint8_t* g1 = cg.ptr<uint8_t>(yb);
    const uint8_t* f = fg.ptr<uint8_t>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < out.cols; ++x) {
      const float xc = (x + 0.5f) * inv_sx - 0.5f;
      const int x0 = static_cast<int>(std::floor(xc));
      const float fx = xc - x0;
      const int xa = std::clamp(x0, 0, cw - 1), xb = std::clamp(x0 + 1, 0, cw - 1);
      const float v[4] = {c0[xa], c0[xb], c1[xa], c1[xb]};
      const float w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
      const uint8_t* g[4] = {g0 + CN * xa, g0 + CN * xb, g1 + CN * xa, g1 + CN * xb};
      const uint8_t* p = f + CN * x;
      int known = 0;
      float lo = std::numeric_limits<float>::max(), hi = -lo, best = nan;
      int best_d = std::numeric_limits<int>::max();
      for (int k = 0; k < 4; ++k) {
        if (!(v[k] == v[k])) continue;  // NaN: unknown
        ++known;
        lo = std::min(lo, v[k]);
        hi = std::max(hi, v[k]);
        const int d = colour_distance<CN>(p, g[k]);
        if (d < best_d) {
          best_d = d;
          best = v[k];
        }
      }
      if (known == 4 && hi - lo <= agree) {
        o[x] = to_full * (w[0] * v[0] + w[1] * v[1] + w[2] * v[2] + w[3] * v[3]);
      } else {
        o[x] = known > 0 ? to_full * best : nan;
      }
    }
  }
}

}  // namespace

void upsample_disparity(const cv::Mat& coarse, const cv::Mat& coarse_guide,
                        const cv::Mat& full_guide, double scale_x, double scale_y, cv::Mat& out,
                        float agree_px) {
  if (coarse.type() != CV_32FC1 || coarse.size() != coarse_guide.size() ||
      coarse_guide.type() != full_guide.type() ||
      (full_guide.type() != CV_8UC1 && full_guide.type() != CV_8UC3) || coarse.empty())
    throw std::invalid_argument(
        "upsample_disparity: expected a CV_32F coarse map, guides of its size and the full "
        "size, both CV_8UC1 or both CV_8UC3");
  out.create(full_guide.size(), CV_32FC1);
  const int cn = full_guide.channels();
  cv::parallel_for_(cv::Range(0, out.rows), [&](const cv::Range& r) {
    if (cn == 3)
      upsample_rows<3>(coarse, coarse_guide, full_guide, scale_x, scale_y, agree_px, out, r.start,
                       r.end);
    else
      upsample_rows<1>(coarse, coarse_guide, full_guide, scale_x, scale_y, agree_px, out, r.start,
                       r.end);
  });
}

}  // namespace hd::recon
