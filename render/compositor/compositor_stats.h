#pragma once
// What a compositor has done since it was made (read by the loop and the benchmark).

#include <cstdint>

namespace hd::render {

struct CompositorStats {
  uint64_t frames_drawn = 0;
  /// Requests refused as malformed (viewport outside `out`, eye size != viewport size, invalid
  /// intrinsics/poses, non-finite values); nothing is drawn for them.
  uint64_t requests_rejected = 0;
  /// Video frames ignored (not RGBA8, empty, stride too small, data too short); the frame is
  /// drawn as if no video was given (synthetic only).
  uint64_t video_frames_rejected = 0;
  uint64_t video_bytes_uploaded = 0;  ///< GL only: texel bytes sent by glTexSubImage2D
  uint64_t video_uploads = 0;         ///< GL only: glTexSubImage2D calls for video
  uint64_t scene_uploads = 0;         ///< GL only: times the synthetic scene was (re)uploaded
  /// Times the model was drawn from the real camera for the model-depth view's seen test (once
  /// per change of model, camera or its pose: not per frame).
  uint64_t camera_depth_renders = 0;
};

}  // namespace hd::render
