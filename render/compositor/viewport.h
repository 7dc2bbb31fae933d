#pragma once
// Where in the output picture one eye is drawn.

namespace hd::render {

/// A rectangle of the output image in pixels, (x, y) its top-left pixel, row 0 at the top.
/// Stereo draws the left eye at x = 0 and the right eye at x = width of the left one.
struct Viewport {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

}  // namespace hd::render
