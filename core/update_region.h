#pragma once
// The part of the camera frame that must be uploaded for the current virtual view.

#include <optional>

#include "core/pixel_rect.h"
#include "core/video_quad.h"
#include "core/view_setup.h"

namespace hd::core {

/// DESIGN.md 1: the real image rectangle placed on z_c = d, clipped by the virtual frustum's
/// half-spaces (4 sides + near), bounding box in real image pixels clamped to the image.
/// nullopt: nothing of the video is visible (no upload, no video), or an invalid setup.
/// Never intersects frustum edges with the plane (they can be parallel to it or point away).
std::optional<PixelRect> update_region(const ViewSetup& s);

/// update_region() from the video quad already clipped by clip_to_virtual_frustum (see
/// coverage_of_clipped_quad).
std::optional<PixelRect> region_of_clipped_quad(const VideoQuad& quad, const CameraPair& pair);

}  // namespace hd::core
