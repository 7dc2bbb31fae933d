#pragma once
// The score run's pictures: score_trace.png (the shown picture's PSNR over the run, the
// background coloured by the variant shown, as trace.png) and m_scatter.png (every frame's m
// against the PSNR of the same frame drawn as pure video and as pure model, with the break-even
// m), for a reader who would rather look than read score.csv.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/transition.h"

namespace hd::station {

/// One eye of one frame, as the plots need it.
struct ScorePoint {
  double t_s = 0.0;
  core::Variant variant = core::Variant::kSynthetic;
  double psnr_db = 0.0;                                 ///< the shown picture
  double m = 0.0;                                       ///< NaN / inf: no camera measured
  double pure_video_db = 0.0, pure_synthetic_db = 0.0;  ///< NaN: not drawn
};

/// BGR, width x height. Throws std::invalid_argument without points.
cv::Mat draw_score_trace(const std::vector<ScorePoint>& points, int width = 1200, int height = 480);
/// BGR; `break_even_m` NaN draws no line. Points without a finite m are left out.
cv::Mat draw_m_scatter(const std::vector<ScorePoint>& points, double break_even_m, int width = 900,
                       int height = 600);

}  // namespace hd::station
