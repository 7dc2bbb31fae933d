#pragma once
// Calibration plus every quality figure the file and the report carry.

#include "calib/calibration_file.h"

namespace hd::calib {

/// Process CPU time in seconds (all threads), for the step timings in IntrinsicsCpu.
double process_cpu_s();

/// calibrate_intrinsics + coverage + cross-validation + warnings, each step's CPU time in `cpu`.
/// Cross-validation (two more calibrations) only with `cross_validate`: the default run costs no
/// more CPU than OpenCV's calibration sample.
IntrinsicsReport assess_intrinsics(const std::vector<View>& views, const Board& board,
                                   cv::Size image_size, const DistortionModel& model,
                                   bool cross_validate = true);

}  // namespace hd::calib
