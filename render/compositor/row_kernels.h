#pragma once
// The CPU compositor's two per-row inner loops -- where each eye pixel samples the video, and the
// blend of video over the model -- each as a scalar reference and an SSE2 version that gives the
// same bytes (x86-64 always has SSE2; elsewhere the SSE2 names fall back to the scalar loops).

#include <cstdint>

namespace hd::render {

/// The homography H (eye pixel -> real pixel) and the plane's inverse depth q along one row:
/// at the pixel centre px = x + 0.5 of this row, h = (h00 px + bx, h10 px + by, h20 px + bw) and
/// 1 / z_eye = q0 px + bz (see VideoWarp).
struct RowWarp {
  double h00 = 0, h10 = 0, h20 = 0, q0 = 0;  ///< coefficients of px
  double bx = 0, by = 0, bw = 0, bz = 0;     ///< the row's constant terms
  double inv_near = 0;                       ///< 1 / near_m: nearer plane points are not video
  double width = 0, height = 0;              ///< the frame, pixels
  float weight = 0;                          ///< video weight of a pixel that sees the frame
};

/// For x in [0, n): u[x], v[x] the real-pixel position (float) and a[x] = weight where the plane
/// point is in front of the eye (1/z in (0, 1/near]) and inside [0, width] x [0, height];
/// u = v = a = 0 elsewhere. The per-pixel arithmetic is double, in exactly this order:
/// iz = q0 px + bz, s = 1 / (h20 px + bw), u = (h00 px + bx) s, v = (h10 px + by) s.
void warp_row_scalar(const RowWarp& w, int n, float* u, float* v, float* a);
void warp_row_sse2(const RowWarp& w, int n, float* u, float* v, float* a);
/// The same bits as warp_row_scalar, four doubles per vector with AVX (no FMA: the same IEEE
/// operations); warp_row_sse2 where the CPU (checked at run time) or the compiler has no AVX.
void warp_row_avx(const RowWarp& w, int n, float* u, float* v, float* a);
/// warp_row_avx where the CPU has AVX, else warp_row_sse2 (the compositor's choice).
void warp_row(const RowWarp& w, int n, float* u, float* v, float* a);

/// What the synthetic part looks like in this row (CompositeRequest's marking styles).
struct RowBlend {
  uint32_t background = 0;  ///< packed RGBA, where the model's depth is 0
  bool desaturate = false;  ///< s += desaturation (grey - s), grey = .299 r + .587 g + .114 b
  float desaturation = 0;
  bool checker = false;  ///< s = clamp(s +- step), + in cells with (x/cell + row) even
  float checker_step = 0;
  int checker_cell_px = 1;
  int checker_row = 0;  ///< y / cell of this row
  float fade = 0;       ///< then s += fade (128 - s): the staleness cue (0: none, s untouched)
};

/// out pixel x (packed RGBA, alpha 255) = round(s + a (v - s)) per channel, in float exactly as
/// written, where s is the model's colour (synth where depth > 0, else background) after the
/// marking, v the video texel `video[x]` and a = a[x] (a == nullptr: 0). x0 is the row's first
/// pixel in the viewport (the checker's phase).
void blend_row_scalar(const RowBlend& b, int x0, int n, const uint8_t* synth, const float* depth,
                      const float* a, const uint32_t* video, uint8_t* out);
void blend_row_sse2(const RowBlend& b, int x0, int n, const uint8_t* synth, const float* depth,
                    const float* a, const uint32_t* video, uint8_t* out);

}  // namespace hd::render
