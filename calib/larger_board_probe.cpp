#include "calib/larger_board_probe.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace hd::calib {

namespace {

constexpr double kMinContrast = 8.0;         ///< grey levels between the edge's two shades
constexpr double kMinOutsideContrast = 0.3;  ///< of that, between the outside squares' shades
constexpr double kContinuedFraction = 0.75;  ///< of an edge's outside squares
constexpr int kMinSquares = 3;               ///< sampled squares for an edge to count
// Where across a row of squares the samples lie, in squares from the pattern's last corner
// line: boards are often cut through their outer squares (OpenCV's own left*.jpg), so both rows
// are sampled near the line, 0.1-0.4 square into the pattern's outer squares and 1.1-1.4 into
// the next ones, and along the edge over the middle half of each square.
constexpr double kAcrossIn = 0.25, kAcrossOut = 1.25, kHalfAcross = 0.15, kHalfAlong = 0.25;

// An edge of the pattern: grid x = c (along a row), y = r; inner corners at integers.
struct Edge {
  bool along_x;  ///< the edge runs along x (the top and bottom edges)
  double line;   ///< its last corner line: x (or y) = 0, cols - 1 (rows - 1)
  double out;    ///< -1 or +1: the direction away from the pattern
};

}  // namespace

LargerBoardProbe probe_beyond_edges(const cv::Mat& gray, const Board& board,
                                    const std::vector<cv::Point2f>& corners) {
  LargerBoardProbe res;
  const int cols = board.cols, rows = board.rows;
  if (gray.type() != CV_8UC1 || static_cast<int>(corners.size()) != board.corner_count()) {
    res.continues = true;
    return res;
  }
  std::vector<cv::Point2f> grid;
  grid.reserve(corners.size());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) grid.emplace_back(static_cast<float>(c), static_cast<float>(r));
  const cv::Mat Hm = cv::findHomography(grid, corners, 0);
  if (Hm.empty()) {
    res.continues = true;
    return res;
  }
  const cv::Matx33d H(Hm);
  auto map = [&](double x, double y) {
    const cv::Vec3d p = H * cv::Vec3d(x, y, 1.0);
    return cv::Point2d(p[0] / p[2], p[1] / p[2]);
  };
  // Mean grey over a 5 (along) x 3 (across) lattice; false if a sample leaves the image.
  auto mean = [&](const Edge& e, double along, double across, cv::Point2d offset, double& out) {
    double sum = 0;
    for (int i = -2; i <= 2; ++i)
      for (int j = -1; j <= 1; ++j) {
        const double a = along + 0.5 * kHalfAlong * i, b = across + kHalfAcross * j;
        const cv::Point2d p = (e.along_x ? map(a, b) : map(b, a)) + offset;
        const int u = static_cast<int>(std::lround(p.x)), v = static_cast<int>(std::lround(p.y));
        if (u < 0 || v < 0 || u >= gray.cols || v >= gray.rows) return false;
        sum += gray.at<uchar>(v, u);
      }
    out = sum / 15.0;
    return true;
  };
  const Edge edges[4] = {
      {false, 0.0, -1}, {false, cols - 1.0, +1}, {true, 0.0, -1}, {true, rows - 1.0, +1}};
  for (const Edge& e : edges) {
    const int n = (e.along_x ? cols : rows) + 1;  // squares along the edge
    const int last = (e.along_x ? cols : rows) - 1;
    std::vector<double> in, out;
    std::vector<int> parity;
    for (int k = 0; k < n; ++k) {
      const double along = k - 0.5;  // square centre along the edge
      // The edge corner nearest the square: its residual against the homography carries the
      // lens's local distortion over to the extrapolated positions.
      const int ka = std::clamp(k, 0, last);
      const int line = static_cast<int>(e.line);
      const cv::Point2f& c =
          corners[static_cast<std::size_t>(e.along_x ? line * cols + ka : ka * cols + line)];
      const cv::Point2d offset = cv::Point2d(c) - (e.along_x ? map(ka, e.line) : map(e.line, ka));
      double vi = 0, vo = 0;
      if (!mean(e, along, e.line + e.out * kAcrossIn, offset, vi) ||
          !mean(e, along, e.line + e.out * kAcrossOut, offset, vo))
        continue;
      in.push_back(vi);
      out.push_back(vo);
      parity.push_back(k & 1);  // the squares along an edge alternate
    }
    if (static_cast<int>(in.size()) < kMinSquares) continue;
    ++res.sides_sampled;
    // The edge's two shades inside; outside, a checker that goes on has them swapped.
    double in_sum[2] = {0, 0}, out_sum[2] = {0, 0};
    int count[2] = {0, 0};
    for (std::size_t k = 0; k < in.size(); ++k) {
      in_sum[parity[k]] += in[k];
      out_sum[parity[k]] += out[k];
      ++count[parity[k]];
    }
    const double in0 = in_sum[0] / count[0], in1 = in_sum[1] / count[1];
    const double out0 = out_sum[0] / count[0], out1 = out_sum[1] / count[1];
    const double contrast = std::abs(in0 - in1);
    if (contrast < kMinContrast) {
      res.continues = true;  // no checker to compare with along this edge: let SB look
      continue;
    }
    const double swapped = in0 > in1 ? out1 - out0 : out0 - out1;  // > 0: shades swapped
    if (swapped < kMinOutsideContrast * contrast) continue;
    const double out_mid = 0.5 * (out0 + out1);
    const int light_parity = in0 > in1 ? 0 : 1;  // inside; outside it is the dark one
    int alternating = 0;
    for (std::size_t k = 0; k < in.size(); ++k)
      alternating += (parity[k] == light_parity) == (out[k] < out_mid);
    if (alternating >= kContinuedFraction * static_cast<double>(in.size())) res.continues = true;
  }
  return res;
}

}  // namespace hd::calib
