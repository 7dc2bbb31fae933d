#pragma once
// View-variant marking (paper VIII) as data: everything a renderer needs to mark which variant
// the operator sees, with no drawing code here.

#include <array>
#include <cstdint>

#include "core/transition.h"

namespace hd::core {

enum class MarkingStyle { kNone, kFrame, kDesaturate, kChecker };

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

struct MarkingParams {
  MarkingStyle style = MarkingStyle::kDesaturate;
  /// kFrame: width of the coloured border around the operator screen.
  int frame_width_px = 8;
  /// kFrame: border colour per Variant, indexed by static_cast<int>(Variant).
  std::array<Rgb, 3> frame_rgb = {Rgb{40, 200, 60}, Rgb{240, 190, 30}, Rgb{220, 50, 40}};
  /// kDesaturate: 0 keeps the synthetic part's colour, 1 turns it to grey (the paper's Fig. 6).
  double synthetic_desaturation = 1.0;
  /// kChecker: cell size and contrast (0..1, fraction of full scale added/removed on alternate
  /// cells) of the checker superimposed on the synthetic part (the paper's Fig. 8).
  int checker_cell_px = 16;
  double checker_contrast = 0.25;

  /// The continuous staleness cue (docs/truth.md), zero for fresh data so that fresh video and a
  /// fresh model look exactly as without it. Set per frame by for_ages():
  /// synthetic_fade (0..1) pulls the marked model colour toward mid-grey (128), video_stale paints
  /// a border of frame_width_px in stale_rgb over the screen (any style but kNone).
  double synthetic_fade = 0.0;
  bool video_stale = false;
  Rgb stale_rgb = {230, 40, 230};
  /// The cue's parameters: below model_age_fresh_ms the model looks as today; at
  /// model_age_full_ms and beyond it is faded by stale_fade_max (and a checker marking's contrast
  /// has grown to stale_checker_contrast), linearly in between.
  double model_age_fresh_ms = 2000.0;
  double model_age_full_ms = 10000.0;
  double stale_fade_max = 0.6;
  double stale_checker_contrast = 0.6;
  /// Video older than this is framed in stale_rgb; 0: 3/4 of the camera's max_video_age.
  double video_age_warn_ms = 0.0;

  const Rgb& frame_colour(Variant v) const { return frame_rgb[static_cast<int>(v)]; }

  /// These parameters with the cue set for a model `model_age_ms` old (NaN: unknown, e.g. the
  /// a-priori model: no cue) and video on screen that is past its warning bound (`video_stale`).
  /// kNone stays unmarked. No allocation.
  MarkingParams for_ages(double model_age_ms, bool video_stale) const;

  /// The same parameters with every number forced into its meaningful range (NaN -> default),
  /// so a renderer never sees a zero cell size or a contrast outside [0,1].
  MarkingParams sanitized() const;
};

}  // namespace hd::core
