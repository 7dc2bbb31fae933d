#pragma once
// One eye of one frame reduced to how wrong the shown picture would be at any video weight: the
// squared error of the compositor's blend as a function of the transition's w_video, so other
// m_t and eps can be scored without drawing the frame again (station/score/transition_tuning.h).
//
// The compositor draws out = s + a (v - s) per pixel and channel: s the model's colour, v the
// video's, a the pixel's video weight. Against the truth t, with b = s - t and d = v - s:
//   SSE(a) = sum over pixels and channels of (b + a d)^2 = B + sum_p (2 a_p BD_p + a_p^2 DD_p),
// B = sum b^2, BD_p = sum_c b d, DD_p = sum_c d^2. Where the video does not reach, v = s and d = 0.
//   - Global blend (and abrupt, whose a is 0 or 1): a_p = w everywhere the video reaches, so
//     SSE(w) = B + 2 w BD + w^2 DD from three sums: exact.
//   - Per-pixel blend: a_p = render::BorderWeight(w)(u_p, v_p), which depends on the pixel only
//     through x' = |1 - 2u/width| and y' = |1 - 2v/height|. BD and DD are summed into a
//     kBins x kBins grid over (x', y') and a is taken at each cell's centre. x' runs over half
//     the frame, so a cell is 1/128 of the frame's width (5 px of 640). Inside the frame's flat
//     middle a is the same for every pixel of a cell, so only the ramp's cells are approximate.
//     On the default scene the replay of the run's own transition is within 0.001 dB (mean) and
//     0.03 dB (worst eye-frame) of the pictures drawn; 128 cells per axis took 4x the time for
//     no better agreement. ScoreRun.TheReplayedTransitionMatchesTheShownPictures checks this.
//
// The pictures: the truth, the model view (CpuCompositor::record_model_only) and the pure video
// view (the same draw at global weight 1, so the video wherever it reaches and the model
// elsewhere) with the positions the video was sampled at (CpuCompositor::record_video_positions).
// The compositor rounds each blended value to 8 bits; the model does not, which adds at most
// 1/12 to a pixel's mean squared error (uniform rounding), below 0.01 dB at 30 dB.

#include <vector>

#include "core/transition.h"
#include "render/compositor/image_rgba8.h"

namespace hd::station {

class BlendErrorModel {
 public:
  static constexpr int kBins = 64;

  /// `positions`: (u, v) per pixel of the pictures, NaN where the video does not reach (nullptr:
  /// no video at all this frame); `frame_width` x `frame_height`: the video frame's size. All
  /// pictures the same size (throws std::invalid_argument).
  void build(const render::ImageRgba8& truth, const render::ImageRgba8& model,
             const render::ImageRgba8& video, const float* positions, int frame_width,
             int frame_height);

  /// The shown picture's squared error summed over pixels and colour channels at video weight
  /// w in [0, 1] (abrupt and global blend alike; kPerPixel through the border weight).
  double sse(core::TransitionMode mode, double w) const;
  /// PSNR of sse(mode, w) over the picture (capped like psnr_db).
  double psnr_db(core::TransitionMode mode, double w) const;
  bool has_video() const { return has_video_; }

 private:
  double values_ = 0.0;  ///< pixels x 3 channels
  double sse_model_ = 0.0, sum_bd_ = 0.0, sum_dd_ = 0.0;
  bool has_video_ = false;
  int frame_width_ = 0, frame_height_ = 0;
  std::vector<double> bin_bd_, bin_dd_;  ///< kBins x kBins over (x', y'), row y'
};

}  // namespace hd::station
