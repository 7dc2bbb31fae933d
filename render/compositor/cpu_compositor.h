#pragma once
// The CPU reference compositor: the ground truth the GL compositor is tested against.

#include <cstdint>
#include <memory>
#include <vector>

#include "render/compositor/camera_depth_map.h"
#include "render/compositor/compositor.h"
#include "render/compositor/depth_warp.h"
#include "render/compositor/mesh_rasterizer.h"
#include "render/compositor/video_warp.h"
#include "render/cpu/row_worker.h"
#include "render/lens/cpu_predistorter.h"
#include "render/overlay/overlay_painter.h"

namespace hd::render {

/// Draws the picture CompositeRequest defines, deterministically: the same request gives the same
/// bytes whatever the thread count (each row is computed by exactly one thread, the same way).
///
/// Speed (see docs/rendering.md): the homography is stepped incrementally along a row, the video
/// is sampled with 8-bit fixed-point bilinear weights, and with N threads the rows are split
/// into N bands, all but the first drawn by persistent worker threads (RowWorker's kBands: they
/// wait on an atomic, no lock, no allocation per frame).
class CpuCompositor final : public Compositor {
 public:
  /// `threads` in 1..RowWorker::kMaxThreads, else std::invalid_argument.
  explicit CpuCompositor(int threads = 1);
  ~CpuCompositor() override;
  CpuCompositor(const CpuCompositor&) = delete;
  CpuCompositor& operator=(const CpuCompositor&) = delete;

  void draw(const CompositeRequest& req, ImageRgba8& out) override;
  void draw_overlay(const Overlay& overlay, const Viewport& vp, ImageRgba8& out) override {
    paint_overlay(overlay, vp, out);
  }
  /// The lens table (lens::CpuPredistorter) with this compositor's thread count.
  void set_lens(const lens::LensWarp* warp) override;
  void predistort(const ImageRgba8& eyes, ImageRgba8& panel) override;
  const CompositorStats& stats() const override { return stats_; }

  /// Keeps each drawn pixel's video weight a (out = s + a (v - s)), 0..255 rounded, in `map`
  /// (one byte per pixel of the output picture, row-major; resized to it when it is not); nullptr
  /// stops it. For `hybrid-station score`, which splits its error by what each pixel showed; costs
  /// nothing when off.
  void record_video_weight(std::vector<uint8_t>* map) { weight_map_ = map; }
  /// Keeps, beside the picture, the same picture with no video in it (a = 0 everywhere: the
  /// model view), resized to the output picture; nullptr stops it. One draw then gives
  /// `hybrid-station score` both pure views: the picture at global weight 1 and this one.
  void record_model_only(ImageRgba8* picture) { model_only_ = picture; }
  /// Keeps where each output pixel samples the video frame, (u, v) in frame pixels at
  /// map[2 (y width + x)], wherever the warp sees the frame (before the per-pixel border weight),
  /// NaN elsewhere; resized to the output picture. For replaying the per-pixel blend at other
  /// weights (station/score/blend_error_model.h).
  void record_video_positions(std::vector<float>* map) { position_map_ = map; }

 private:
  struct Frame;  // per-draw constants shared by the bands
  /// Rows [row_begin, row_end) with band `band`'s scratch (0: the caller's, 1..: a worker's).
  void draw_band(int row_begin, int row_end, int band);
  /// Row y of the viewport into position_map_: (u, v) where a > 0, NaN elsewhere (u == nullptr:
  /// the whole row NaN).
  void record_positions(int y, const float* u, const float* v, const float* a);

  MeshRasterizer rasterizer_;
  std::vector<uint8_t> synth_rgba_;  ///< viewport-sized synthetic colour
  std::vector<float> inv_depth_;     ///< viewport-sized depth (1/z, 0 = empty)
  std::vector<float> scratch_;       ///< per band: kRowGroup rows of sample u, v, video weight
  std::vector<uint32_t> video_row_;  ///< per band: kRowGroup rows of sampled video texels
  std::vector<int> fixed_;           ///< per band: kRowGroup rows of 1/256 px positions X, Y
  CompositorStats stats_;

  const CompositeRequest* req_ = nullptr;  ///< valid during draw only
  ImageRgba8* out_ = nullptr;
  const SyntheticScene* scene_ = nullptr;
  VideoWarp warp_;
  bool video_on_ = false;
  DepthWarp depth_warp_;         ///< the model-depth view's warp (kModelDepth)
  CameraDepthMap camera_depth_;  ///< the model seen from the real camera, for its seen test
  bool depth_view_ = false;
  std::vector<uint8_t>* weight_map_ = nullptr;
  ImageRgba8* model_only_ = nullptr;
  std::vector<float>* position_map_ = nullptr;

  std::unique_ptr<lens::CpuPredistorter> lens_;

  int threads_ = 1;
  RowWorker rows_;  ///< last: its thread stops before the members it draws with go
};

}  // namespace hd::render
