#pragma once
// Calibration plus every quality figure the file and the report carry.

#include "calib/calibration_file.h"

namespace hd::calib {

/// calibrate_intrinsics + coverage + cross-validation + warnings.
IntrinsicsReport assess_intrinsics(const std::vector<View>& views, const Board& board,
                                   cv::Size image_size, const DistortionModel& model);

}  // namespace hd::calib
