#pragma once
// Whether a requested region of interest fits a GigE camera's Width/Height limits, and which
// offset to ask for: the checks made before the region is written, so a refusal says why.

#include <string>

namespace hd::drivers {

/// A camera's Width and Height features: bounds and increments in (binned) pixels. A value is
/// accepted when it is within [min, max] and min + a multiple of the increment.
struct RegionLimits {
  int width_min_px = 0;
  int width_max_px = 0;
  int height_min_px = 0;
  int height_max_px = 0;
  int width_step_px = 1;
  int height_step_px = 1;
};

/// "16..1024 x 16..768 px", with " in steps of 4x2" when a step is above 1.
std::string limits_text(const RegionLimits& limits);

/// Why the camera cannot take a `width_px` x `height_px` region ("Width 2000 is outside the
/// camera's 16..1024", both axes joined by ", "); empty when both fit.
std::string region_size_refusal(const RegionLimits& limits, int width_px, int height_px);

/// The offset to ask for on one axis: `wanted_px` when it is >= 0; else the camera's current
/// offset when a region of `size_px` still fits on the sensor from there (or the sensor size is
/// unknown, `sensor_px` <= 0), else 0.
int region_offset_to_ask(int wanted_px, int current_px, int size_px, int sensor_px);

}  // namespace hd::drivers
