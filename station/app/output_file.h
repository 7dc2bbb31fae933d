#pragma once
// Output files appear whole or not at all: written beside their name, then renamed into place.

#include <opencv2/core.hpp>
#include <string>

#include "render/compositor/image_rgba8.h"

namespace hd::station {

/// Encodes `bgr` (8-bit, 1 or 3 channels) to a temp file beside `path` and renames it into
/// place. Throws std::runtime_error naming the file on failure (the temp file is removed).
void write_png_atomically(const cv::Mat& bgr, const std::string& path);

/// Writes `text` the same way.
void write_text_atomically(const std::string& text, const std::string& path);

/// A BGR copy of an RGBA8 picture (OpenCV's channel order, for imwrite and VideoWriter).
void rgba_to_bgr(const render::ImageRgba8& rgba, cv::Mat& bgr);

}  // namespace hd::station
