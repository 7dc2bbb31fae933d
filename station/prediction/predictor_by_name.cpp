#include "station/prediction/predictor_by_name.h"

#include "station/prediction/constant_velocity_predictor.h"
#include "station/prediction/kalman_predictor.h"

namespace hd::station {

std::unique_ptr<PosePredictor> make_predictor(const std::string& name) {
  if (name == "none") return std::make_unique<HoldPredictor>();
  if (name == "cv") return std::make_unique<ConstantVelocityPredictor>();
  return std::make_unique<KalmanPredictor>();
}

}  // namespace hd::station
