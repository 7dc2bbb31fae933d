#include "render/overlay/hud_strip.h"

#include <algorithm>
#include <atomic>
#include <opencv2/imgproc.hpp>

namespace hd::render {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

// Glyph height ~60 % of a line, whatever the line's height.
double font_scale(int line_height_px) {
  int baseline = 0;
  const cv::Size unit = cv::getTextSize("Hg", kFont, 1.0, 1, &baseline);
  return 0.6 * line_height_px / std::max(1, unit.height + baseline);
}

int text_width(const std::string& s, double scale) {
  int baseline = 0;
  return cv::getTextSize(s, kFont, scale, 1, &baseline).width;
}

// Splits `text` into pieces that each end just after a break opportunity; the separator stays
// with the piece before it, so pieces concatenate back to the text.
std::vector<std::string> pieces(std::string_view text, std::string_view sep) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t at = text.find(sep, start);
    if (at == std::string_view::npos) break;
    out.emplace_back(text.substr(start, at + sep.size() - start));
    start = at + sep.size();
  }
  if (start < text.size()) out.emplace_back(text.substr(start));
  return out;
}

std::string trim_right(std::string s) {
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

std::string trim_left(std::string s) {
  s.erase(0, s.find_first_not_of(' '));
  return s;
}

}  // namespace

HudStrip::HudStrip(int width_px, int line_height_px, int max_lines, int graph_lines)
    : line_height_(std::max(8, line_height_px)),
      max_lines_(std::max(1, max_lines)),
      graph_lines_(std::max(0, graph_lines)) {
  if (width_px > 0) {
    image_.allocate(width_px, capacity_height());
    image_.height = line_height_;
  }
  text_.reserve(256);
}

std::vector<std::string> HudStrip::layout(std::string_view text, int width_px, int line_height_px,
                                          int max_lines) {
  const double scale = font_scale(std::max(8, line_height_px));
  const int room = std::max(1, width_px - 2 * kMarginPx);
  auto fits = [&](const std::string& s) { return text_width(trim_right(s), scale) <= room; };
  std::vector<std::string> lines;
  std::string rest(text);
  while (!rest.empty()) {
    if (fits(rest)) {
      lines.push_back(trim_right(rest));
      break;
    }
    // The longest prefix ending at a break, preferring the coarsest separator that gives one.
    std::string line;
    for (std::string_view sep : {" | ", "  ", " "}) {
      std::string acc;
      for (const std::string& p : pieces(rest, sep)) {
        if (!fits(acc + p)) break;
        acc += p;
      }
      if (!acc.empty()) {
        line = acc;
        break;
      }
    }
    if (line.empty()) {  // one word wider than the strip: as many characters as fit
      std::size_t n = 1;
      while (n < rest.size() && fits(rest.substr(0, n + 1))) ++n;
      line = rest.substr(0, n);
    }
    // A line broken at " | " ends at the field, not at a dangling separator.
    std::string shown = trim_right(line);
    if (shown.size() > 1 && shown.back() == '|')
      shown = trim_right(shown.substr(0, shown.size() - 1));
    lines.push_back(shown);
    rest = trim_left(rest.substr(line.size()));
  }
  if (static_cast<int>(lines.size()) > std::max(1, max_lines)) {
    lines.resize(static_cast<std::size_t>(std::max(1, max_lines)));
    std::string& last = lines.back();
    while (!last.empty() && !fits(last + "...")) last.pop_back();
    last = trim_right(last) + "...";
  }
  return lines;
}

bool HudStrip::set_text(std::string_view text, const HudGraph& graph) {
  text = text.substr(0, std::min<std::size_t>(text.size(), 255));
  if (text == text_ && graph == graph_) return false;
  text_.assign(text.begin(), text.end());
  graph_ = graph;
  // Unique across strips, so a new strip at a freed one's address never looks already uploaded.
  static std::atomic<uint64_t> next_revision{0};
  revision_ = ++next_revision;
  if (image_.empty()) return true;
  const std::vector<std::string> lines =
      text_.empty() ? std::vector<std::string>{}
                    : layout(text_, image_.width, line_height_, max_lines_);
  line_count_ = std::max<int>(1, static_cast<int>(lines.size()));
  const int graph_height = shows_graph() ? graph_lines_ * line_height_ : 0;
  image_.height = line_count_ * line_height_ + graph_height;
  cv::Mat strip(image_.height, image_.width, CV_8UC4, image_.data.data(),
                static_cast<std::size_t>(image_.stride_bytes));
  strip.setTo(cv::Scalar(0, 0, 0, kBackgroundAlpha));
  const double scale = font_scale(line_height_);
  int baseline = 0;
  const cv::Size unit = cv::getTextSize("Hg", kFont, 1.0, 1, &baseline);
  const int ascent = static_cast<int>(unit.height * scale + 0.5);
  const int descent = static_cast<int>(baseline * scale + 0.5);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const cv::Point org(kMarginPx,
                        static_cast<int>(i) * line_height_ + (line_height_ + ascent - descent) / 2);
    cv::putText(strip, lines[i], org, kFont, scale, cv::Scalar(255, 255, 255, 255), 1, cv::LINE_AA);
  }
  if (graph_height > 0) {
    cv::Mat area = strip.rowRange(line_count_ * line_height_, image_.height);
    draw_hud_graph(area, graph_);
  }
  return true;
}

}  // namespace hd::render
