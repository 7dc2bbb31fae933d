#include "calib/distortion_model.h"

#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace hd::calib {

int DistortionModel::cv_flags() const {
  int f = 0;
  if (terms == Terms::rational8) f |= cv::CALIB_RATIONAL_MODEL;
  if (terms == Terms::fix_k3) f |= cv::CALIB_FIX_K3;
  if (fix_aspect) f |= cv::CALIB_FIX_ASPECT_RATIO;
  return f;
}

std::string DistortionModel::name() const {
  std::string s = terms == Terms::k5 ? "5" : terms == Terms::rational8 ? "rational" : "fix-k3";
  if (fix_aspect) s += "+fix-aspect";
  return s;
}

DistortionModel DistortionModel::parse(const std::string& s) {
  DistortionModel m;
  if (s == "5") return m;
  if (s == "8" || s == "rational") {
    m.terms = Terms::rational8;
    return m;
  }
  if (s == "fix-k3") {
    m.terms = Terms::fix_k3;
    return m;
  }
  if (s == "fix-aspect") {
    m.fix_aspect = true;
    return m;
  }
  throw std::invalid_argument("--model '" + s + "': expected 5, 8, rational, fix-k3 or fix-aspect");
}

}  // namespace hd::calib
