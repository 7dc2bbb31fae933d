#pragma once
// The chessboard a technician holds: inner-corner grid and square size.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace hd::calib {

/// A chessboard described by its INNER corners (OpenCV's pattern size), columns x rows.
struct Board {
  int cols = 0;
  int rows = 0;
  double square_m = 0.0;

  cv::Size pattern() const { return {cols, rows}; }
  int corner_count() const { return cols * rows; }
  /// Board-frame corner positions (z = 0), row-major as OpenCV's detectors return them.
  std::vector<cv::Point3f> object_points() const;

  /// Parses "9x6" (cols x rows, each >= 2) and a square > 0; throws std::invalid_argument naming
  /// the option on bad input.
  static Board parse(const std::string& cols_x_rows, double square_m);
};

}  // namespace hd::calib
