#pragma once
// C: the fraction of the operator's screen the video quad fills.

#include "core/video_quad.h"
#include "core/view_setup.h"

namespace hd::core {

/// Analytic coverage (DESIGN.md 4): the real image rectangle on z_c = d, clipped to z_o >= near,
/// projected into the virtual image, clipped to the screen; its area / screen area, in [0,1].
/// 0 for an invalid setup. No allocation.
double coverage(const ViewSetup& s);

/// coverage() from the video quad already clipped by clip_to_virtual_frustum, so measure_view
/// builds and clips the quad once for both coverage and the update region.
double coverage_of_clipped_quad(const VideoQuad& quad, const ViewSetup& s);

}  // namespace hd::core
