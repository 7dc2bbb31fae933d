#pragma once
// An axis-aligned rectangle in continuous pixel coordinates.

namespace hd::core {

/// [u_min, u_max] x [v_min, v_max] in pixels; the image spans [0,width] x [0,height].
struct PixelRect {
  double u_min = 0.0;
  double v_min = 0.0;
  double u_max = 0.0;
  double v_max = 0.0;

  double width_px() const { return u_max - u_min; }
  double height_px() const { return v_max - v_min; }
};

}  // namespace hd::core
