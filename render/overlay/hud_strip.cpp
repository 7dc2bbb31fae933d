#include "render/overlay/hud_strip.h"

#include <algorithm>
#include <atomic>
#include <opencv2/imgproc.hpp>

namespace hd::render {

HudStrip::HudStrip(int width_px, int height_px) {
  if (width_px > 0) image_.allocate(width_px, std::max(8, height_px));
  text_.reserve(256);
}

bool HudStrip::set_text(std::string_view text) {
  text = text.substr(0, std::min<std::size_t>(text.size(), 255));
  if (text == text_) return false;
  text_.assign(text.begin(), text.end());
  // Unique across strips, so a new strip at a freed one's address never looks already uploaded.
  static std::atomic<uint64_t> next_revision{0};
  revision_ = ++next_revision;
  if (image_.empty()) return true;
  cv::Mat strip(image_.height, image_.width, CV_8UC4, image_.data.data(),
                static_cast<std::size_t>(image_.stride_bytes));
  strip.setTo(cv::Scalar(0, 0, 0, kBackgroundAlpha));
  if (text_.empty()) return true;
  // Glyph height ~60 % of the strip, whatever the strip's height.
  constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
  int baseline = 0;
  const cv::Size unit = cv::getTextSize("Hg", kFont, 1.0, 1, &baseline);
  const double scale = 0.6 * image_.height / std::max(1, unit.height + baseline);
  const int ascent = static_cast<int>(unit.height * scale + 0.5);
  const int descent = static_cast<int>(baseline * scale + 0.5);
  const cv::Point org(4, (image_.height + ascent - descent) / 2);
  cv::putText(strip, text_, org, kFont, scale, cv::Scalar(255, 255, 255, 255), 1, cv::LINE_AA);
  return true;
}

}  // namespace hd::render
