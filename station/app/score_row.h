#pragma once
// One eye of one displayed frame as `hybrid-station score` scored it: a row of score.csv.

#include <cmath>
#include <cstdint>
#include <string>

#include "core/transition.h"
#include "station/score/image_scores.h"

namespace hd::station {

struct ScoreRow {
  uint64_t frame = 0;
  double t_s = 0.0;  ///< scene time of its display
  int eye = 0;
  core::Variant variant = core::Variant::kSynthetic;
  std::string camera;  ///< the camera whose video is drawn ("" none)
  double m = NAN, w_video = 0.0;
  ImageScores whole;
  /// PSNR over the pixels that showed video only (weight 1), a blend (0 < weight < 1), the model
  /// only (weight 0); NaN when there were none.
  double psnr_video_db = NAN, psnr_blend_db = NAN, psnr_synthetic_db = NAN;
  double video_fraction = 0.0;  ///< the mean per-pixel video weight
  /// The share of pixels whose content was older than the bound at the display time: those
  /// showing mostly video (weight >= 1/2) when the video frame was, the others when the model's
  /// textures were. The a-priori model's textures have no capture time and never count.
  double old_fraction = 0.0;
  /// The same frame drawn as pure video (the camera on screen, or the one chosen, at weight 1)
  /// and as pure model; NaN for pure video when no camera was usable.
  double psnr_pure_video_db = NAN, psnr_pure_synthetic_db = NAN;
};

}  // namespace hd::station
