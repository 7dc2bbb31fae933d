#pragma once
// A cheap look past the found pattern's edges: does the checker pattern go on there?

#include <opencv2/core.hpp>
#include <vector>

#include "calib/board.h"

namespace hd::calib {

/// What the probe saw beyond the four edges of a found COLSxROWS pattern.
struct LargerBoardProbe {
  bool continues = false;  ///< some edge is followed by more squares of the board's checker
  int sides_sampled = 0;   ///< edges with enough of the next row of squares inside the image
};

/// Predicts, with the homography from the board's square grid to the found corners (corrected
/// by the nearest edge corner's residual, which absorbs the lens's local distortion), where the
/// squares one row / column beyond each edge of the pattern lie, and samples their mean grey
/// (25 pixels per square, about 30 squares). An edge "continues" when at least 3/4 of its
/// outside squares are the opposite shade of the square inside them, by at least a quarter of
/// the board's contrast along that edge: a white margin or a plain background matches only half
/// of them. Costs microseconds; findChessboardCornersSB with CALIB_CB_LARGER (tens of ms, and
/// fooled by steep views of a board with a white margin) is then needed only where this says
/// the pattern continues. `corners` are row-major (as OpenCV's detectors return them); an
/// ill-conditioned pattern or an edge that shows no checker contrast answers `continues`, so the
/// expensive check still runs whenever this one cannot tell.
LargerBoardProbe probe_beyond_edges(const cv::Mat& gray, const Board& board,
                                    const std::vector<cv::Point2f>& corners);

}  // namespace hd::calib
