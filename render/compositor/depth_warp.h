#pragma once
// The video on the model's depth: eye pixel + the model's inverse depth there -> real pixel,
// and whether the real camera saw that surface point.

#include <Eigen/Core>

#include "core/pinhole.h"
#include "core/pose.h"

namespace hd::render {

/// For an eye pixel p = (u, v, 1) (continuous; a pixel centre is (x+0.5, y+0.5)) that sees a
/// surface point at inverse depth iz = 1 / z_eye:
///   h = A p + b iz,  q = (h0 / h2, h1 / h2) the real pixel,  1 / z_real = iz / h2,
/// with A = K_c R K_o^-1 and b = K_c t, (R, t) the eye frame to the real camera's. The plane
/// view (VideoWarp) is the case iz = VideoWarp::inv_depth . p: its H is A + b inv_depth^T.
struct DepthWarp {
  bool usable = false;  ///< false: invalid intrinsics or poses
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();

  static DepthWarp make(const core::Pinhole& eye, const core::Pose& T_world_eye,
                        const core::Pinhole& real, const core::Pose& T_world_real);
};

/// Whether the real camera sees a point at inverse depth iz_point (1 / z_real) through the texel
/// whose nearest model surface is at iz_seen (0: no model there), with the relative depth
/// tolerance kSeenTolerance. Looking the seen depth up at the nearest texel (not at the point's
/// exact position) is off by up to half a texel's footprint times the surface's slope: at 500 px
/// focal length and a surface at 79 degrees to the ray that is 0.5 % of z; 2 % keeps every
/// surface the camera saw within it while a surface 2 cm behind another at 1 m is hidden.
inline constexpr float kSeenTolerance = 0.02f;
inline bool seen_by_real(float iz_point, float iz_seen) {
  return iz_point >= iz_seen * (1.0f - kSeenTolerance);
}

/// One row of the model-depth view (CompositeRequest's kModelDepth): at the pixel centre
/// px = x + 0.5, h = (a00 px + cx, a10 px + cy, a20 px + cw) + b iz with iz the eye's model depth
/// at x; where the model has no surface (iz = 0) the plane's iz = q0 px + bz is used instead
/// (the plane view there, no seen test).
struct DepthRow {
  double a00 = 0, a10 = 0, a20 = 0;  ///< A's first column (coefficients of px)
  double cx = 0, cy = 0, cw = 0;     ///< the row's constant terms of A p
  double b0 = 0, b1 = 0, b2 = 0;     ///< b
  double q0 = 0, bz = 0;             ///< the plane's inverse depth along the row
  double inv_near = 0;               ///< 1 / near_m: nearer points are not video
  double width = 0, height = 0;      ///< the frame, pixels
  float weight = 0;                  ///< video weight of a pixel that sees the frame
  /// The model's inverse depth seen from the real camera (1 / z_real, 0 = nothing), one float
  /// per frame pixel, seen_width x seen_height, row-major; nullptr: no seen test.
  const float* seen = nullptr;
  int seen_width = 0, seen_height = 0;
};

/// For x in [0, n): u[x], v[x] the real pixel and a[x] = weight where the point is in front of
/// both cameras (1 / z_eye in (0, 1/near], h2 > 0) and q inside [0, width] x [0, height];
/// u = v = a = 0 elsewhere. real_iz[x] = the model point's 1 / z_real where the seen test is
/// still due (a > 0 on a model surface, w.seen set), else 0. `eye_iz` is the row of the eye's
/// model depth (1 / z_eye, 0 = nothing).
void depth_warp_row(const DepthRow& w, int n, const float* eye_iz, float* u, float* v, float* a,
                    float* real_iz);
/// The same bits one pixel at a time: the reference depth_warp_row's AVX loop (four doubles per
/// vector, no FMA: the same IEEE operations; used where the CPU has no AVX) is tested against.
void depth_warp_row_scalar(const DepthRow& w, int n, const float* eye_iz, float* u, float* v,
                           float* a, float* real_iz);
/// The seen test of pixels [x_begin, x_end) of a row depth_warp_row computed: a[x] = 0 where the
/// real camera did not see the point. Separate so that the caller can run it in the same tiles
/// as its video sampling: the seen map is read where the frame is, which a turned warp walks
/// across many rows (and pages) within one eye row.
void seen_test_row(const DepthRow& w, int x_begin, int x_end, const float* u, const float* v,
                   const float* real_iz, float* a);

}  // namespace hd::render
