#pragma once
// A line of text for the operator's window (latency, variant), drawn once per text change.

#include <cstdint>
#include <string>
#include <string_view>

#include "render/compositor/image_rgba8.h"

namespace hd::render {

/// A preallocated RGBA strip holding one line of text: white glyphs on translucent black.
/// set_text() renders with cv::putText only when the text changed; OpenCV may allocate while it
/// does, so the station calls it outside the per-frame path (every ~0.5 s). The per-frame blit
/// (paint_overlay, GlCompositor::draw_overlay) only reads image() and revision().
class HudStrip {
 public:
  /// Sized once here. height_px below 8 is raised to 8; width_px below 1 makes an empty strip.
  explicit HudStrip(int width_px = 0, int height_px = 22);

  /// Renders `text` (clipped to 255 characters and to the strip's width) if it differs from the
  /// current text; returns whether it re-rendered. Empty text: nothing is drawn on screen.
  bool set_text(std::string_view text);

  std::string_view text() const { return text_; }
  bool empty() const { return text_.empty() || image_.empty(); }
  const ImageRgba8& image() const { return image_; }
  /// Changes at every re-render (unique across strips): the GL compositor re-uploads on change.
  uint64_t revision() const { return revision_; }

  static constexpr uint8_t kBackgroundAlpha = 160;

 private:
  ImageRgba8 image_;
  std::string text_;
  uint64_t revision_ = 0;
};

}  // namespace hd::render
