#pragma once
// trace.png: m and w_video over the run, with the m_t +- eps band and the variant shown as the
// background colour, so one picture shows when and why the view changed.

#include <opencv2/core.hpp>
#include <string>

#include "core/transition.h"
#include "station/app/frame_log.h"

namespace hd::station {

/// Background colours per variant (BGR), also used by the contact sheet's labels.
cv::Scalar variant_shade_bgr(core::Variant v);

/// The plot as an image (BGR, `width` x `height`): top panel m (y axis from 0 to a bound that
/// keeps the band readable; values above it, and +inf, sit on the top edge), bottom panel
/// w_video in [0, 1]; the x axis is t_s. Throws std::invalid_argument for an empty log.
cv::Mat draw_trace(const FrameLog& log, const core::TransitionParams& transition, int width = 1200,
                   int height = 720);

/// draw_trace() written atomically to `path`.
void write_trace_png(const FrameLog& log, const core::TransitionParams& transition,
                     const std::string& path);

}  // namespace hd::station
