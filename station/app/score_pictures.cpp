// The score run's error map, its scale bar and the shown | truth | error contact sheet.
#include "station/app/score_pictures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "station/app/plot_axes.h"

namespace hd::station {
namespace {

// The map's colour of every error 0..255 DN, built once: OpenCV's INFERNO (perceptually
// uniform, black at zero, so "no error" reads as nothing) over the fixed 0..64 DN scale.
const std::array<cv::Vec3b, 256>& colour_of_error() {
  static const std::array<cv::Vec3b, 256> table = [] {
    cv::Mat index(1, 256, CV_8UC1), colours;
    for (int e = 0; e < 256; ++e)
      index.at<uint8_t>(0, e) = static_cast<uint8_t>(
          std::lround(std::min(e, kErrorMapFullScaleDn) * 255.0 / kErrorMapFullScaleDn));
    cv::applyColorMap(index, colours, cv::COLORMAP_INFERNO);
    std::array<cv::Vec3b, 256> t{};
    for (int e = 0; e < 256; ++e) t[static_cast<std::size_t>(e)] = colours.at<cv::Vec3b>(0, e);
    return t;
  }();
  return table;
}

std::string size_text(const render::ImageRgba8& im) {
  return std::to_string(im.width) + "x" + std::to_string(im.height);
}

// `picture` fitted into a w x h tile of `sheet` at (x, y), centred, keeping its aspect ratio;
// grey when there is no picture.
void place(cv::Mat& sheet, const cv::Mat& picture, int x, int y, int w, int h) {
  cv::Mat tile = sheet(cv::Rect(x, y, w, h));
  if (picture.empty()) {
    tile.setTo(cv::Scalar(128, 128, 128));
    return;
  }
  const double s =
      std::min(static_cast<double>(w) / picture.cols, static_cast<double>(h) / picture.rows);
  const int pw = std::clamp(static_cast<int>(std::lround(picture.cols * s)), 1, w);
  const int ph = std::clamp(static_cast<int>(std::lround(picture.rows * s)), 1, h);
  cv::Mat fitted;
  if (pw == picture.cols && ph == picture.rows)
    fitted = picture;
  else
    cv::resize(picture, fitted, cv::Size(pw, ph), 0, 0, cv::INTER_AREA);
  fitted.copyTo(tile(cv::Rect((w - pw) / 2, (h - ph) / 2, pw, ph)));
}

const cv::Mat* first_picture(const std::vector<SheetRow>& rows) {
  for (const SheetRow& r : rows)
    for (const cv::Mat* m : {&r.shown, &r.truth, &r.error})
      if (!m->empty()) return m;
  return nullptr;
}

}  // namespace

cv::Vec3b error_colour_bgr(int dn) {
  return colour_of_error()[static_cast<std::size_t>(std::clamp(dn, 0, 255))];
}

cv::Mat error_map(const render::ImageRgba8& shown, const render::ImageRgba8& truth) {
  if (shown.width != truth.width || shown.height != truth.height)
    throw std::invalid_argument("error map: the shown picture is " + size_text(shown) +
                                " but the truth is " + size_text(truth));
  if (shown.empty()) return {};
  const auto& colour = colour_of_error();
  cv::Mat map(shown.height, shown.width, CV_8UC3);
  for (int y = 0; y < shown.height; ++y) {
    const uint8_t* s = shown.row(y);
    const uint8_t* t = truth.row(y);
    cv::Vec3b* out = map.ptr<cv::Vec3b>(y);
    for (int x = 0; x < shown.width; ++x, s += 4, t += 4) {
      int e = 0;
      for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(int(s[c]) - int(t[c])));
      out[x] = colour[static_cast<std::size_t>(e)];
    }
  }
  return map;
}

cv::Mat error_legend(int width_px) {
  if (width_px < 64)
    throw std::invalid_argument("error legend: " + std::to_string(width_px) +
                                " px is too narrow (at least 64)");
  constexpr int kHeight = 36, kRampTop = 2, kRamp = 14;
  cv::Mat img(kHeight, width_px, CV_8UC3, cv::Scalar(255, 255, 255));
  const plot::Axis x{0, width_px - 1, 0.0, static_cast<double>(kErrorMapFullScaleDn)};
  for (int px = 0; px < width_px; ++px) {
    const int dn = static_cast<int>(std::lround(kErrorMapFullScaleDn * px / (width_px - 1.0)));
    cv::line(img, {px, kRampTop}, {px, kRampTop + kRamp - 1}, cv::Scalar(error_colour_bgr(dn)));
  }
  for (int dn = 0; dn <= kErrorMapFullScaleDn; dn += 16) {
    const int at = x.px(dn);
    cv::line(img, {at, kRampTop + kRamp}, {at, kRampTop + kRamp + 3}, cv::Scalar(0, 0, 0));
    const std::string s = dn == kErrorMapFullScaleDn ? plot::number(dn) + "+ DN" : plot::number(dn);
    int base = 0;
    const int w = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, 0.4, 1, &base).width;
    // Centred on the tick, but kept inside the bar at both ends.
    plot::text(img, s, {std::clamp(at - w / 2, 0, width_px - w), kHeight - 4}, 0.4);
  }
  return img;
}

cv::Mat score_contact_sheet(const std::vector<SheetRow>& rows) {
  if (rows.empty()) throw std::invalid_argument("score contact sheet: no rows");
  const cv::Mat* first = first_picture(rows);
  if (first == nullptr) throw std::invalid_argument("score contact sheet: no row has a picture");
  // A wrong type is the caller's bug (RGBA handed over unconverted): said, not drawn grey.
  for (const SheetRow& r : rows)
    for (const cv::Mat* m : {&r.shown, &r.truth, &r.error})
      if (!m->empty() && m->type() != CV_8UC3)
        throw std::invalid_argument("score contact sheet: row '" + r.label +
                                    "' has a picture that is not BGR 8-bit");
  constexpr int kPad = 6, kTitle = 26, kLabel = 22, kLegend = 36;
  const double s =
      std::min(1.0, static_cast<double>(kSheetMaxWidthPx - 4 * kPad) / (3.0 * first->cols));
  const int tw = std::max(1, static_cast<int>(std::floor(first->cols * s)));
  const int th = std::max(1, static_cast<int>(std::floor(first->rows * s)));
  const bool legend = tw >= 64;  // error_legend's narrowest
  const int n = static_cast<int>(rows.size());
  const int width = kPad + 3 * (tw + kPad);
  const int height = kTitle + n * (kLabel + th + kPad) + (legend ? kLegend + kPad : 0);
  cv::Mat sheet(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const char* titles[3] = {"shown", "truth", "error: max |shown - truth| of R, G, B"};
  const double title_scale = std::min(0.5, 0.5 * tw / 320.0);
  for (int c = 0; c < 3; ++c)
    plot::text(sheet, titles[c], {kPad + c * (tw + kPad), kTitle - 8}, title_scale);
  for (int r = 0; r < n; ++r) {
    const SheetRow& row = rows[static_cast<std::size_t>(r)];
    const int y = kTitle + r * (kLabel + th + kPad);
    plot::text(sheet, row.label, {kPad, y + kLabel - 6}, std::min(0.5, 0.5 * 3 * tw / 600.0));
    const cv::Mat* pictures[3] = {&row.shown, &row.truth, &row.error};
    for (int c = 0; c < 3; ++c)
      place(sheet, *pictures[c], kPad + c * (tw + kPad), y + kLabel, tw, th);
  }
  if (legend)
    error_legend(tw).copyTo(
        sheet(cv::Rect(kPad + 2 * (tw + kPad), kTitle + n * (kLabel + th + kPad), tw, kLegend)));
  return sheet;
}

}  // namespace hd::station
