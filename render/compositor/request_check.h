#pragma once
// The checks both compositors apply to a request, so they refuse exactly the same inputs.

#include "render/compositor/composite_request.h"
#include "render/compositor/image_rgba8.h"

namespace hd::render {

/// The viewport lies inside `out` (whose buffer is large enough), the eye's size equals the
/// viewport's, the eye intrinsics and pose are valid, 0 < near_m < far_m, all finite.
bool request_drawable(const CompositeRequest& req, const ImageRgba8& out);

/// req.video is an RGBA8 frame of real.width x real.height with a whole-pixel stride and enough
/// data, the real camera's intrinsics and pose are valid, d_m > 0, the region is finite.
/// Call only with req.video != nullptr.
bool video_usable(const CompositeRequest& req);

}  // namespace hd::render
