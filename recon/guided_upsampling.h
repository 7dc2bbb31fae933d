#pragma once
// Brings a disparity map computed on a downscaled pair back to full resolution, guided by the
// full-resolution left image so that depth edges stay on image edges.

#include <opencv2/core.hpp>

namespace hd::recon {

/// `coarse`: CV_32F disparity of the downscaled left image in coarse pixels, NaN = unknown.
/// `coarse_guide` / `full_guide`: that downscaled left image and the full one (CV_8UC1 or
/// CV_8UC3, the same type). scale_x = full width / coarse width, scale_y likewise; coarse pixel
/// i is centred on full coordinate (i + 0.5) * scale_x - 0.5 (cv::resize's mapping, OpenCV pixel
/// centres).
///
/// Each full pixel looks at its 2x2 coarse neighbours: where all four are known and lie within
/// `agree_px` coarse pixels of each other (one surface) it takes their bilinear value; otherwise
/// (an edge, a hole next to it) the known neighbour whose guide colour is nearest to the full
/// pixel's own (the surface it belongs to); no known neighbour: unknown. The result is in full
/// pixels (coarse value * scale_x), CV_32F, full_guide's size, NaN = unknown.
void upsample_disparity(const cv::Mat& coarse, const cv::Mat& coarse_guide,
                        const cv::Mat& full_guide, double scale_x, double scale_y, cv::Mat& out,
                        float agree_px = 1.0f);

}  // namespace hd::recon
