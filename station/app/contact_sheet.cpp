#include "station/app/contact_sheet.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "station/app/frames_csv.h"
#include "station/app/output_file.h"
#include "station/app/trace_plot.h"

namespace hd::station {

ThumbnailSet::ThumbnailSet(std::size_t capacity, int tile_width_px, int image_width_px,
                           int image_height_px, uint64_t initial_stride)
    : capacity_(std::max<std::size_t>(capacity, 4)),
      tile_w_(std::max(tile_width_px, 16)),
      tile_h_(std::max(1, static_cast<int>(std::lround(static_cast<double>(tile_w_) *
                                                       std::max(image_height_px, 1) /
                                                       std::max(image_width_px, 1))))),
      stride_(std::max<uint64_t>(initial_stride, 1)),
      tiles_(capacity_),
      metas_(capacity_) {
  for (cv::Mat& t : tiles_) t = cv::Mat(tile_h_, tile_w_, CV_8UC3, cv::Scalar::all(0));
  rgba_scaled_ = cv::Mat(tile_h_, tile_w_, CV_8UC4, cv::Scalar::all(0));
}

void ThumbnailSet::add(const render::ImageRgba8& image, const FrameMeta& meta) {
  if (image.empty()) return;
  if (count_ == capacity_) decimate();
  if (meta.frame % stride() != 0) return;  // offered before the stride doubled
  const cv::Mat view(image.height, image.width, CV_8UC4, const_cast<uint8_t*>(image.data.data()),
                     static_cast<std::size_t>(image.stride_bytes));
  cv::resize(view, rgba_scaled_, cv::Size(tile_w_, tile_h_), 0, 0, cv::INTER_AREA);
  cv::cvtColor(rgba_scaled_, tiles_[count_], cv::COLOR_RGBA2BGR);
  metas_[count_] = meta;
  ++count_;
}

void ThumbnailSet::decimate() {
  const uint64_t next = stride() * 2;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    if (metas_[i].frame % next != 0) continue;
    if (kept != i) {
      std::swap(tiles_[kept], tiles_[i]);  // swaps headers: no pixel copy, no allocation
      metas_[kept] = metas_[i];
    }
    ++kept;
  }
  count_ = kept;
  stride_.store(next, std::memory_order_relaxed);
}

std::vector<std::size_t> ThumbnailSet::pick(std::size_t n) const {
  std::vector<std::size_t> picks;
  if (count_ == 0 || n == 0) return picks;
  std::vector<std::size_t> changes{0};
  for (std::size_t i = 1; i < count_; ++i)
    if (metas_[i].variant != metas_[i - 1].variant) changes.push_back(i);
  // Room for the changes (thinned evenly if the view flickered) ...
  const std::size_t room = std::max<std::size_t>(1, n * 2 / 3);
  if (changes.size() <= room) {
    picks = changes;
  } else {
    for (std::size_t k = 0; k < room; ++k)
      picks.push_back(changes[k * (changes.size() - 1) / std::max<std::size_t>(room - 1, 1)]);
  }
  // ... and the last candidate, so the sheet ends where the run ended.
  if (std::find(picks.begin(), picks.end(), count_ - 1) == picks.end() && picks.size() < n)
    picks.push_back(count_ - 1);
  // Fill with the candidates farthest in time from every pick so far.
  while (picks.size() < std::min(n, count_)) {
    std::size_t best = 0;
    double best_gap = -1.0;
    for (std::size_t i = 0; i < count_; ++i) {
      double gap = std::numeric_limits<double>::infinity();
      for (std::size_t p : picks) gap = std::min(gap, std::abs(metas_[i].t_s - metas_[p].t_s));
      if (gap > best_gap) {
        best_gap = gap;
        best = i;
      }
    }
    if (best_gap <= 0.0) break;
    picks.push_back(best);
  }
  std::sort(picks.begin(), picks.end());
  picks.erase(std::unique(picks.begin(), picks.end()), picks.end());
  return picks;
}

void ThumbnailSet::set_extra_tile(const cv::Mat& bgr, std::string label) {
  extra_ = cv::Mat(tile_h_, tile_w_, CV_8UC3, cv::Scalar(40, 40, 40));
  if (!bgr.empty()) {
    const double s =
        std::min(static_cast<double>(tile_w_) / bgr.cols, static_cast<double>(tile_h_) / bgr.rows);
    const int w = std::max(1, static_cast<int>(bgr.cols * s)),
              h = std::max(1, static_cast<int>(bgr.rows * s));
    cv::Mat fitted;
    cv::resize(bgr, fitted, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    fitted.copyTo(extra_(cv::Rect((tile_w_ - w) / 2, (tile_h_ - h) / 2, w, h)));
  }
  extra_label_ = std::move(label);
}

cv::Mat ThumbnailSet::compose(std::size_t n, int columns) const {
  const std::vector<std::size_t> picks = pick(n);
  if (picks.empty()) throw std::invalid_argument("contact sheet: no frames");
  constexpr int kLabel = 22, kPad = 6;
  const std::size_t tiles = picks.size() + (extra_.empty() ? 0 : 1);
  const int cols = std::min<int>(columns, static_cast<int>(tiles));
  const int rows = (static_cast<int>(tiles) + cols - 1) / cols;
  const int cell_w = tile_w_ + kPad, cell_h = tile_h_ + kLabel + kPad;
  cv::Mat sheet(rows * cell_h + kPad, cols * cell_w + kPad, CV_8UC3, cv::Scalar(40, 40, 40));
  for (std::size_t k = 0; k < picks.size(); ++k) {
    const std::size_t i = picks[k];
    const int x = kPad + static_cast<int>(k % static_cast<std::size_t>(cols)) * cell_w;
    const int y = kPad + static_cast<int>(k / static_cast<std::size_t>(cols)) * cell_h;
    tiles_[i].copyTo(sheet(cv::Rect(x, y, tile_w_, tile_h_)));
    const FrameMeta& m = metas_[i];
    cv::rectangle(sheet, cv::Rect(x, y + tile_h_, tile_w_, kLabel), variant_shade_bgr(m.variant),
                  cv::FILLED);
    char label[96];
    if (std::isfinite(m.m))
      std::snprintf(label, sizeof label, "#%" PRIu64 " %.1fs %s m=%.1f", m.frame, m.t_s,
                    variant_name(m.variant), m.m);
    else
      std::snprintf(label, sizeof label, "#%" PRIu64 " %.1fs %s m=inf", m.frame, m.t_s,
                    variant_name(m.variant));
    const double scale = std::min(0.45, 0.45 * tile_w_ / 300.0);
    cv::putText(sheet, label, {x + 4, y + tile_h_ + 16}, cv::FONT_HERSHEY_SIMPLEX, scale,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  if (!extra_.empty()) {
    const std::size_t k = picks.size();
    const int x = kPad + static_cast<int>(k % static_cast<std::size_t>(cols)) * cell_w;
    const int y = kPad + static_cast<int>(k / static_cast<std::size_t>(cols)) * cell_h;
    extra_.copyTo(sheet(cv::Rect(x, y, tile_w_, tile_h_)));
    cv::rectangle(sheet, cv::Rect(x, y + tile_h_, tile_w_, kLabel), cv::Scalar(200, 120, 200),
                  cv::FILLED);
    const double scale = std::min(0.4, 0.4 * tile_w_ / 300.0);
    cv::putText(sheet, extra_label_, {x + 4, y + tile_h_ + 16}, cv::FONT_HERSHEY_SIMPLEX, scale,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  return sheet;
}

void write_contact_sheet(const ThumbnailSet& thumbs, const std::string& path, std::size_t tiles) {
  if (thumbs.size() == 0) throw std::runtime_error(path + ": no frames to show");
  write_png_atomically(thumbs.compose(tiles), path);
}

}  // namespace hd::station
