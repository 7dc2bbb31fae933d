#include "calib/board.h"

#include <cmath>
#include <stdexcept>

namespace hd::calib {

std::vector<cv::Point3f> Board::object_points() const {
  std::vector<cv::Point3f> pts;
  pts.reserve(static_cast<std::size_t>(corner_count()));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      pts.emplace_back(static_cast<float>(c * square_m), static_cast<float>(r * square_m), 0.0f);
  return pts;
}

Board Board::parse(const std::string& cols_x_rows, double square_m) {
  const auto x = cols_x_rows.find_first_of("xX");
  Board b;
  try {
    if (x == std::string::npos) throw std::invalid_argument("no 'x'");
    std::size_t used = 0;
    b.cols = std::stoi(cols_x_rows.substr(0, x), &used);
    if (used != x) throw std::invalid_argument("junk");
    const std::string rows = cols_x_rows.substr(x + 1);
    b.rows = std::stoi(rows, &used);
    if (used != rows.size()) throw std::invalid_argument("junk");
  } catch (const std::exception&) {
    throw std::invalid_argument("--board '" + cols_x_rows +
                                "': expected inner corners as COLSxROWS, e.g. 9x6");
  }
  if (b.cols < 2 || b.rows < 2 || b.cols > 100 || b.rows > 100)
    throw std::invalid_argument("--board '" + cols_x_rows +
                                "': each dimension must be 2..100 inner corners");
  if (!std::isfinite(square_m) || square_m <= 0.0 || square_m > 10.0)
    throw std::invalid_argument("--square " + std::to_string(square_m) +
                                ": expected the square size in metres, > 0 (e.g. 0.025)");
  b.square_m = square_m;
  return b;
}

}  // namespace hd::calib
