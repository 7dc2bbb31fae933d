#pragma once
// Everything one eye's picture depends on, for one frame.

#include "core/marking.h"
#include "core/pinhole.h"
#include "core/pixel_rect.h"
#include "core/pose.h"
#include "core/transition.h"
#include "core/video_view.h"
#include "drivers/frame.h"
#include "render/compositor/synthetic_scene.h"
#include "render/compositor/video_sampling.h"
#include "render/compositor/viewport.h"

namespace hd::render {

/// One eye, one frame. Plain data: the caller owns everything pointed to and keeps it alive and
/// unchanged for the duration of `Compositor::draw`.
///
/// Picture, per output pixel p of the viewport (pixel centre (x+0.5, y+0.5) in eye pixels):
///   synth(p)  = the scene's meshes seen by the eye (depth-tested, perspective-correct, bilinear
///               texture), or the background; then the marking's synthetic-part modification
///               (desaturation or checker) if the style asks for it;
///   video(p)  = the frame sampled at q = H p, H the homography induced by the plane z_c = d_m in
///               the real camera (eye pixel -> real pixel), if the plane point lies in front of the
///               eye (z_eye >= near_m) and q lies inside [0,width] x [0,height] of the frame;
///               with video_view kModelDepth, where the eye sees a model surface point X instead
///               q = X's projection into the real camera, and only if the real camera saw X
///               (depth_warp.h's seen test against the model drawn from P_c); where the eye
///               sees no model surface, the plane's q;
///   a(p)      = coverage(p) * weight, weight = transition.w_video for kAbrupt / kGlobalBlend, and
///               core::continuous_pixel_weight(w_video, q.u, q.v, real.width, real.height) for
///               kPerPixel (the paper's w2, made continuous in m: DESIGN 7);
///   out(p)    = a * video(p) + (1 - a) * synth(p), rounded to nearest, alpha 255;
///   then the frame marking (style kFrame) is painted over the viewport's border.
/// No video (video == nullptr, has_region == false, or a rejected frame): a = 0 everywhere.
struct CompositeRequest {
  /// The synthetic model; nullptr draws the background colour of a default SyntheticScene.
  const SyntheticScene* scene = nullptr;

  /// The eye (virtual camera p_o, P_o). eye.width x eye.height must equal the viewport's size.
  core::Pinhole eye;
  core::Pose T_world_eye;  ///< camera-to-world, X_world = R X_eye + t
  double near_m = 0.05;  ///< eye near plane: mesh triangles are clipped here; video needs z >= near
  double far_m = 100.0;  ///< eye far plane: geometry beyond it is not drawn

  /// The newest frame of the chosen camera; nullptr = no video. Must be kRgba8 with
  /// real.width x real.height pixels (undistorted, i.e. matching the pinhole `real`).
  const drivers::Frame* video = nullptr;
  core::Pinhole real;       ///< the real camera's intrinsics p_c
  core::Pose T_world_real;  ///< its pose P_c, camera-to-world
  double d_m = 1.0;         ///< the plane z_c = d_m (real camera frame) the video is projected on
  /// kPlane and kFittedPlane draw the plane at d_m (a fitted plane's d is the caller's);
  /// kModelDepth lays the video on the scene's meshes.
  core::VideoView video_view = core::VideoView::kPlane;

  /// The part of the frame that is visible this frame (core::measure_view's update region, real
  /// pixels, continuous coordinates). The GL compositor uploads only this rectangle (grown to
  /// whole pixels plus a one-pixel margin for bilinear sampling); the CPU compositor samples the
  /// frame directly. has_region == false means the video is not visible: no upload, no video.
  core::PixelRect region{0.0, 0.0, 0.0, 0.0};
  bool has_region = false;

  core::TransitionState transition{core::Variant::kSynthetic, 0.0, 1.0};
  core::TransitionMode mode = core::TransitionMode::kPerPixel;
  core::MarkingParams marking{};
  VideoSampling sampling = VideoSampling::kBilinear;

  /// Where in `out` this eye is drawn; pixels outside it are left untouched.
  Viewport viewport;

  /// GL only: read the viewport back into `out` (glReadPixels). The CPU compositor always fills.
  bool read_back = true;
};

}  // namespace hd::render
