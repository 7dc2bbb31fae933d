#pragma once
// contact_sheet.png: a dozen labelled tiles picked along the run so one picture shows the view
// going video -> hybrid -> synthetic and back.

#include <atomic>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/transition.h"
#include "render/compositor/image_rgba8.h"

namespace hd::station {

/// What a tile is labelled with.
struct FrameMeta {
  uint64_t frame = 0;
  double t_s = 0.0;
  core::Variant variant = core::Variant::kSynthetic;
  double m = 0.0;
  double w_video = 0.0;
};

/// Downscaled candidates for the sheet, sampled every stride() frames into `capacity` slots
/// allocated up front. When the slots are full, every other candidate is dropped and the stride
/// doubles, so any run length ends with evenly spread candidates in fixed memory.
/// add() and pick() run on one thread (the recorder's); stride() may be read from any thread.
class ThumbnailSet {
 public:
  /// Every slot is allocated and written here (tile height from the pictures' aspect ratio), so
  /// filling them later does not grow the process's resident memory.
  ThumbnailSet(std::size_t capacity, int tile_width_px, int image_width_px, int image_height_px,
               uint64_t initial_stride);

  uint64_t stride() const { return stride_.load(std::memory_order_relaxed); }
  /// Whether the render thread should hand this frame over.
  bool wants(uint64_t frame) const { return frame % stride() == 0; }
  /// Downscales `image` (of the size given at construction) into the next slot.
  void add(const render::ImageRgba8& image, const FrameMeta& meta);

  std::size_t size() const { return count_; }
  const FrameMeta& meta(std::size_t i) const { return metas_[i]; }

  /// Indices of up to `n` candidates in time order: the first one, the first after every change
  /// of variant (evenly thinned if there are more changes than room), then the candidates
  /// farthest in time from those already picked.
  std::vector<std::size_t> pick(std::size_t n) const;

  /// One more tile, after the picked ones: a picture that is not a frame of the run (the model
  /// tile: the newest model with its reconstructed part tinted). Fitted into a tile, `label`
  /// under it. Set after the run, on the thread that composes.
  void set_extra_tile(const cv::Mat& bgr, std::string label);

  /// The sheet: picked tiles in rows of `columns`, each labelled "#frame t variant m", then the
  /// extra tile if one was set.
  cv::Mat compose(std::size_t n = 12, int columns = 4) const;

 private:
  void decimate();

  std::size_t capacity_;
  int tile_w_, tile_h_;
  std::atomic<uint64_t> stride_;
  std::vector<cv::Mat> tiles_;
  std::vector<FrameMeta> metas_;
  std::size_t count_ = 0;
  cv::Mat rgba_scaled_;
  cv::Mat extra_;  ///< tile-sized BGR, empty = none
  std::string extra_label_;
};

/// compose() written atomically to `path`; throws naming the file when there is no candidate.
void write_contact_sheet(const ThumbnailSet& thumbs, const std::string& path,
                         std::size_t tiles = 12);

}  // namespace hd::station
