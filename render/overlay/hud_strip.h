#pragma once
// Text for the operator's window (latency, variant, ages), laid out to fit and drawn once per
// text change.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "render/compositor/image_rgba8.h"
#include "render/overlay/hud_graph.h"

namespace hd::render {

/// A preallocated RGBA strip holding up to `max_lines` lines of text: white glyphs on translucent
/// black. The text is never cut off at the strip's edge: a line too wide for the strip wraps at
/// the text's separators (" | ", two spaces, then one space), and what does not fit in
/// `max_lines` lines is shortened to end in "..." (layout()). image() is as tall as the lines
/// used (its buffer holds max_lines, so a change of line count allocates nothing).
///
/// set_text() renders with cv::putText only when the text changed; OpenCV may allocate while it
/// does, so the station calls it outside the per-frame path (every ~0.5 s). The per-frame blit
/// (paint_overlay, GlCompositor::draw_overlay) only reads image() and revision().
class HudStrip {
 public:
  /// Sized once here. line_height_px below 8 is raised to 8, max_lines below 1 to 1; width_px
  /// below 1 makes an empty strip. graph_lines: the height, in lines, a graph takes below the
  /// text (0: no graph is ever drawn).
  explicit HudStrip(int width_px = 0, int line_height_px = 22, int max_lines = 1,
                    int graph_lines = 0);

  /// Lays out and renders `text` (clipped to 255 characters) if it differs from the current
  /// text; returns whether it re-rendered. Empty text: nothing is drawn on screen.
  bool set_text(std::string_view text) { return set_text(text, HudGraph{}); }
  /// The same with `graph` below the text (an empty graph: none), re-rendered when either
  /// changed.
  bool set_text(std::string_view text, const HudGraph& graph);

  std::string_view text() const { return text_; }
  bool empty() const { return text_.empty() || image_.empty(); }
  /// The used lines (line_count() * line height rows); the buffer behind it holds max_lines.
  const ImageRgba8& image() const { return image_; }
  int line_count() const { return line_count_; }
  int capacity_height() const { return line_height_ * (max_lines_ + graph_lines_); }
  bool shows_graph() const { return !graph_.empty() && graph_lines_ > 0; }
  /// Changes at every re-render (unique across strips): the GL compositor re-uploads on change.
  uint64_t revision() const { return revision_; }

  /// The lines `text` is shown as in a strip `width_px` wide with glyphs of `line_height_px`
  /// lines: every line's drawn width fits, at most `max_lines` lines, the last ending in "..."
  /// when text had to be left out.
  static std::vector<std::string> layout(std::string_view text, int width_px, int line_height_px,
                                         int max_lines);

  static constexpr uint8_t kBackgroundAlpha = 160;
  static constexpr int kMarginPx = 4;  ///< left and right of the text

 private:
  ImageRgba8 image_;
  std::string text_;
  HudGraph graph_;
  int line_height_ = 22;
  int max_lines_ = 1;
  int graph_lines_ = 0;
  int line_count_ = 1;
  uint64_t revision_ = 0;
};

}  // namespace hd::render
