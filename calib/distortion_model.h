#pragma once
// Which distortion terms calibration estimates (a knob: more terms fit better but may be
// poorly determined by the views).

#include <string>

namespace hd::calib {

struct DistortionModel {
  enum class Terms { k5, rational8, fix_k3 } terms = Terms::k5;
  bool fix_aspect = false;  ///< fx/fy fixed at 1 (CALIB_FIX_ASPECT_RATIO)

  /// OpenCV calibrateCamera flags.
  int cv_flags() const;
  std::string name() const;
  /// "5" | "8" | "rational" | "fix-k3" | "fix-aspect" (= 5 with fixed aspect); throws
  /// std::invalid_argument naming --model otherwise.
  static DistortionModel parse(const std::string& s);
};

}  // namespace hd::calib
