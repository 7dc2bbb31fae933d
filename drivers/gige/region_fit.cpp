// Region of interest against a GigE camera's Width/Height bounds and increments.
#include "drivers/gige/region_fit.h"

namespace hd::drivers {

namespace {

// Why `v` is not an acceptable value of feature `name`; empty when it is.
std::string value_refusal(const char* name, int v, int lo, int hi, int inc) {
  if (v < lo || v > hi)
    return std::string(name) + " " + std::to_string(v) + " is outside the camera's " +
           std::to_string(lo) + ".." + std::to_string(hi);
  if ((v - lo) % inc != 0)
    return std::string(name) + " " + std::to_string(v) + " is not " + std::to_string(lo) +
           " + a multiple of " + std::to_string(inc);
  return {};
}

}  // namespace

std::string limits_text(const RegionLimits& l) {
  std::string out = std::to_string(l.width_min_px) + ".." + std::to_string(l.width_max_px) + " x " +
                    std::to_string(l.height_min_px) + ".." + std::to_string(l.height_max_px) +
                    " px";
  if (l.width_step_px > 1 || l.height_step_px > 1)
    out +=
        " in steps of " + std::to_string(l.width_step_px) + "x" + std::to_string(l.height_step_px);
  return out;
}

std::string region_size_refusal(const RegionLimits& l, int width_px, int height_px) {
  std::string why =
      value_refusal("Width", width_px, l.width_min_px, l.width_max_px, l.width_step_px);
  const std::string hy =
      value_refusal("Height", height_px, l.height_min_px, l.height_max_px, l.height_step_px);
  why += (why.empty() || hy.empty() ? "" : ", ") + hy;
  return why;
}

int region_offset_to_ask(int wanted_px, int current_px, int size_px, int sensor_px) {
  if (wanted_px >= 0) return wanted_px;
  return sensor_px <= 0 || current_px + size_px <= sensor_px ? current_px : 0;
}

}  // namespace hd::drivers
