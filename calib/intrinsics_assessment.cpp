#include "calib/intrinsics_assessment.h"

#include <time.h>

#include "calib/intrinsics_uncertainty.h"

namespace hd::calib {

double process_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

IntrinsicsReport assess_intrinsics(const std::vector<View>& views, const Board& board,
                                   cv::Size image_size, const DistortionModel& model,
                                   bool with_cross_validation) {
  IntrinsicsReport rep;
  rep.board = board;
  rep.model_name = model.name();
  const double t0 = process_cpu_s();
  rep.result = calibrate_intrinsics(views, board, image_size, model, nullptr, false);
  const double ts = process_cpu_s();
  rep.result.std_dev_intrinsics = intrinsics_std_dev(views, board, rep.result);
  const double t1 = process_cpu_s();
  if (with_cross_validation)
    rep.cross_validation = cross_validate(views, board, image_size, model, &rep.result);
  const double t2 = process_cpu_s();
  rep.coverage = coverage(views, rep.result);
  rep.warnings = quality_warnings(rep.result, rep.coverage, rep.cross_validation);
  const double t3 = process_cpu_s();
  rep.cpu.calibration_s = ts - t0;
  rep.cpu.sigma_s = t1 - ts;
  rep.cpu.cross_validation_s = t2 - t1;
  rep.cpu.coverage_s = t3 - t2;
  return rep;
}

}  // namespace hd::calib
