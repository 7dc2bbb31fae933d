#pragma once
// The head-pose predictor a station file or the command line names: "none" (hold the newest
// sample), "cv" (constant velocity) or "kalman" (the default; anything else is kalman too, as
// the option checks have already refused other names).

#include <memory>
#include <string>

#include "station/prediction/pose_predictor.h"

namespace hd::station {

std::unique_ptr<PosePredictor> make_predictor(const std::string& name);

}  // namespace hd::station
