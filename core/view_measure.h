#pragma once
// The per-frame verdict on one camera's video: E_max, coverage C, m = E_max / C, update region.

#include "core/pixel_rect.h"
#include "core/view_setup.h"

namespace hd::core {

struct ViewMeasure {
  double e_max_px;   ///< max of E over W's vertices; 0 when W is empty; +inf possible
  double coverage;   ///< C in [0,1]
  double m;          ///< E_max / C; +inf when C = 0 or E_max = +inf
  bool has_region;   ///< false: nothing of the frame is visible, upload nothing
  PixelRect region;  ///< valid when has_region; real image pixels, clamped to the image
};

/// DESIGN.md 1-4 for one camera. E_max is evaluated at every vertex of W (a vertex on a near plane
/// counts as in front). Invalid setup (NaN, non-positive d/near/focal length, bad rotation,
/// min > max box): e_max = +inf, coverage = 0, m = +inf, no region. Never NaN. No heap allocation.
ViewMeasure measure_view(const ViewSetup& s);

/// E_max over W's vertices alone (same rules as measure_view).
double max_error_at_vertices(const ViewSetup& s);

}  // namespace hd::core
