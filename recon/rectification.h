#pragma once
// Rectification of a calibrated stereo pair: both images resampled so that a workspace point
// appears in the same row of both, at column x_right = x_left - d (d the disparity, > 0).

#include <opencv2/core.hpp>

#include "recon/stereo_rig.h"

namespace hd::recon {

/// The rectified geometry of a StereoRig (cv::stereoRectify with CALIB_ZERO_DISPARITY, so points
/// at infinity have d = 0 and every point in front of both cameras has d > 0), and the resampling
/// maps of both cameras.
///
/// Pixel coordinates here are OpenCV's (pixel centres at integers) in the rectified images, whose
/// size is the left image's. The rig must be horizontal (the baseline, in the rectified frame,
/// along +x from left to right) and both cameras must have the same image size.
class Rectification {
 public:
  /// alpha as cv::stereoRectify: 0 keeps only pixels both cameras really have (no black border,
  /// some of the view cropped), 1 keeps every source pixel. Throws RigError (a message naming the
  /// camera and the reason) for an invalid rig, different image sizes, a vertical baseline, a
  /// right camera on the left, or an epipole inside an image (one camera in front of the other:
  /// no planar rectification exists).
  explicit Rectification(const StereoRig& rig, double alpha = 0.0);

  const StereoRig& rig() const { return rig_; }
  cv::Size size() const { return size_; }
  /// (x, y, d, 1) in the rectified left image -> homogeneous point in the rectified left frame.
  const cv::Matx44d& Q() const { return Q_; }
  /// X_rect = R_rect_left * X_left (the rotation of the left camera into the rectified frame).
  const cv::Matx33d& R_rect_left() const { return R1_; }
  double focal_px() const { return focal_px_; }  ///< rectified focal length (fx = fy)
  double baseline_m() const { return baseline_m_; }
  /// Rectified depth of disparity d (> 0): Z = f B / d, metres along the rectified axis.
  double depth_m(double disparity_px) const { return focal_px_ * baseline_m_ / disparity_px; }

  /// Resamples a left / right image (the camera's own size, any type remap takes) into `out`.
  void rectify_left(const cv::Mat& in, cv::Mat& out) const;
  void rectify_right(const cv::Mat& in, cv::Mat& out) const;

  /// Where rectified left pixel (x, y) comes from in the original left image (OpenCV pixel
  /// coordinates, CV_32F, the rectified size). Texture coordinates of the left image use it.
  const cv::Mat& left_map_x() const { return left_x_; }
  const cv::Mat& left_map_y() const { return left_y_; }

  /// The share of the left camera's view (a grid of its pixels) that the right camera also sees
  /// at some depth in [z_near_m, z_far_m] along the left camera's rays (ideal pinholes).
  double overlap_fraction(double z_near_m, double z_far_m) const;

 private:
  StereoRig rig_;
  cv::Size size_;
  cv::Matx33d R1_, R2_;
  cv::Matx34d P1_, P2_;
  cv::Matx44d Q_;
  double focal_px_ = 0.0;
  double baseline_m_ = 0.0;
  cv::Mat left_x_, left_y_, right_x_, right_y_;
};

}  // namespace hd::recon
