#pragma once
// recon/'s OpenCV-typed view of a core::Pinhole (pixel centres at +0.5, DESIGN.md "Conventions")
// as OpenCV's camera matrix (pixel centres at integers); the half pixel itself is converted only
// in core/opencv_pixels.h, which these functions forward to.

#include <opencv2/core.hpp>

#include "core/pinhole.h"

namespace hd::recon {

/// OpenCV's K for a pinhole: the same focal lengths, the principal point moved by -0.5 px so
/// that OpenCV's pixel (i, j) is core's continuous point (i + 0.5, j + 0.5).
cv::Matx33d opencv_camera_matrix(const core::Pinhole& p);

/// The pinhole's distortion coefficients as OpenCV takes them (a 1 x n row; n = 0 gives an empty
/// matrix, which OpenCV reads as "no distortion").
cv::Mat opencv_distortion(const core::Pinhole& p);

/// The inverse of opencv_camera_matrix: a pinhole from an OpenCV K, distortion and image size
/// (distortion: 0, 4, 5 or 8 coefficients; other counts throw std::invalid_argument).
core::Pinhole pinhole_from_opencv(const cv::Matx33d& K, const cv::Mat& distortion, int width,
                                  int height);

}  // namespace hd::recon
