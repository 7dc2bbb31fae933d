#include "calib/intrinsics_assessment.h"

namespace hd::calib {

IntrinsicsReport assess_intrinsics(const std::vector<View>& views, const Board& board,
                                   cv::Size image_size, const DistortionModel& model) {
  IntrinsicsReport rep;
  rep.board = board;
  rep.model_name = model.name();
  rep.result = calibrate_intrinsics(views, board, image_size, model);
  rep.coverage = coverage(views, rep.result);
  rep.cross_validation = cross_validate(views, board, image_size, model);
  rep.warnings = quality_warnings(rep.result, rep.coverage, rep.cross_validation);
  return rep;
}

}  // namespace hd::calib
