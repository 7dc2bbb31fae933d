#pragma once
// A picture of one colour, opaque: the simplest input with a known answer for the station's
// picture tests.

#include <cstdint>

#include "render/compositor/image_rgba8.h"

namespace hd::station::testing {

inline render::ImageRgba8 solid_image(int w, int h, uint8_t r, uint8_t g, uint8_t b) {
  render::ImageRgba8 im;
  im.allocate(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t* p = im.pixel(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    }
  return im;
}

}  // namespace hd::station::testing
