#pragma once
// How the video is laid into the eye's picture: on the paper's plane, on a plane fitted to the
// model each frame, or on the model's own depth (docs/video-views.md).

#include <optional>
#include <string_view>

namespace hd::core {

/// kPlane: the paper's view, the frame projected onto the plane z_c = d at the camera's fixed d.
/// kFittedPlane: the same warp, with d chosen every frame from the model's depth where the eye
///   sees the frame, smoothed in time (station/video/fitted_plane.h); E, W and m as the paper
///   defines them, at that d.
/// kModelDepth: each eye pixel samples the frame where the model's surface point it sees
///   projects into the real camera, if the real camera sees that point (a depth test against the
///   model seen from P_c); elsewhere the model fills in (render/compositor/depth_warp.h).
enum class VideoView { kPlane, kFittedPlane, kModelDepth };

/// "plane", "fitted-plane", "model-depth": the names in station and scene files and on the
/// command line.
constexpr std::string_view video_view_name(VideoView v) {
  switch (v) {
    case VideoView::kPlane:
      return "plane";
    case VideoView::kFittedPlane:
      return "fitted-plane";
    case VideoView::kModelDepth:
      return "model-depth";
  }
  return "plane";
}

/// The view named `name` (video_view_name's spelling), nullopt for anything else.
constexpr std::optional<VideoView> parse_video_view(std::string_view name) {
  for (VideoView v : {VideoView::kPlane, VideoView::kFittedPlane, VideoView::kModelDepth})
    if (name == video_view_name(v)) return v;
  return std::nullopt;
}

}  // namespace hd::core
