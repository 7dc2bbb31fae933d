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

  const Rgb& frame_colour(Variant v) const { return frame_rgb[static_cast<int>(v)]; }

  /// The same parameters with every number forced into its meaningful range (NaN -> default),
  /// so a renderer never sees a zero cell size or a contrast outside [0,1].
  MarkingParams sanitized() const;
};

}  // namespace hd::core
