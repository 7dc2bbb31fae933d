#pragma once
// Blend weights between video and synthetic view (paper VII with DESIGN.md 5-7's corrections).

namespace hd::core {

/// Global video weight (DESIGN 5, the paper's w1 with its sign corrected):
///   w_video = clamp((m_t + eps - m) / (2 eps), 0, 1);  eps = 0: 1 for m <= m_t, else 0.
/// m = +inf, NaN m, NaN m_t, negative or non-finite eps: 0 (synthetic is the safe side).
double video_weight(double m, double m_t, double eps);

/// The paper's per-pixel weight w2 (DESIGN 6, corner term corrected): with x' = |1 - 2u/width|,
/// y' = |1 - 2v/height| (clamped to [0,1]), the border of relative width kappa ramps linearly,
/// the corners are rounded about (1-kappa, 1-kappa), w'2 is clamped to [0,1] and shaped by
/// w2 = (sin((w'2 - 0.5) pi) + 1) / 2. (u,v) are video-frame pixels.
/// kappa is clamped to [0,1]; NaN kappa/u/v or a non-positive size: 0. kappa = 0: 1 everywhere.
/// Note: at kappa = 1 the frame centre still has weight 1 -- the jump DESIGN 7 warns about.
double pixel_weight(double kappa, double u, double v, double width, double height);

/// The continuous per-pixel rule the station uses (DESIGN 7):
///   w = min(1, 2 w_video) * pixel_weight(min(1, 2 (1 - w_video)), u, v, ...)
/// For w_video in [1/2, 1] the border grows from nothing to the whole frame (kappa' = 0 .. 1) at
/// full strength; for w_video in [0, 1/2] the fully-bordered frame fades out as a whole. Both
/// factors are continuous in w_video, so the weight is continuous in m across the whole band:
/// w_video = 1 gives pure video (1 everywhere), w_video = 0 gives pure synthetic (0 everywhere).
/// NaN w_video: 0.
double continuous_pixel_weight(double w_video, double u, double v, double width, double height);

}  // namespace hd::core
