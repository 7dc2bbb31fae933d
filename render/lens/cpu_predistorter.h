#pragma once
// The CPU pre-distortion pass: both eyes warped through the inverse lens model into the panel.

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "render/compositor/image_rgba8.h"
#include "render/lens/lens_warp.h"

namespace hd::render::lens {

/// Fills the HMD panel's picture from the eyes' picture (the StereoRig layout: two eye images of
/// warp.eye_width() x warp.eye_height() side by side). Each panel pixel takes R, G and B from
/// the eye image at the points LensWarp::source gives for its centre, sampled bilinearly with
/// 8-bit fixed-point weights (the CPU compositor's sampler; clamped to the pixel's own eye
/// image); alpha is 255, and pixels beyond the usable lens radius are opaque black.
///
/// The lookup table is built once in the constructor: per panel pixel the green sample's position
/// in 1/256 px (two int32), and per row and eye the span of usable pixels. R and B need no
/// entries of their own: in the lens model their offsets from the eye's principal point are the
/// green one scaled by aberration[c] / aberration[G], exactly (done in 16.16 fixed point). apply()
/// allocates nothing; with threads = 2 the rows are split into two bands, one done by a persistent
/// worker woken through an atomic.
class CpuPredistorter {
 public:
  /// `simd`: use the AVX2 row kernel when the CPU has it (the same bytes as the scalar one).
  CpuPredistorter(const LensWarp& warp, int threads = 1, bool simd = true);
  ~CpuPredistorter();
  CpuPredistorter(const CpuPredistorter&) = delete;
  CpuPredistorter& operator=(const CpuPredistorter&) = delete;

  /// `eyes` must be at least 2 * eye_width x eye_height, `panel` allocated to the panel's size;
  /// false (nothing written) otherwise.
  bool apply(const ImageRgba8& eyes, ImageRgba8& panel);

  /// The same picture with every sample point evaluated from the lens polynomial per pixel and
  /// channel (double precision), no table: the reference the benchmark times the table against.
  bool apply_exact(const ImageRgba8& eyes, ImageRgba8& panel) const;

  const LensWarp& warp() const { return warp_; }

 private:
  struct Span {
    int begin = 0, end = 0;  ///< usable panel columns [begin, end) of one eye in one row
  };
  void band(int row_begin, int row_end);
  void worker_loop();

  LensWarp warp_;
  /// Per panel pixel: the green sample in the eyes' picture, 256 * (u - 0.5, v - 0.5).
  std::vector<int32_t> positions_;
  std::vector<Span> spans_;                         ///< [row * 2 + eye]
  int32_t scale_fixed_[3] = {65536, 65536, 65536};  ///< channel_scale * 2^16
  int32_t centre_fixed_[2][2] = {};                 ///< principal points, as positions_

  const ImageRgba8* eyes_ = nullptr;  ///< valid during apply only
  ImageRgba8* panel_ = nullptr;

  bool simd_ = false;
  int threads_ = 1;
  std::thread worker_;
  std::atomic<uint64_t> job_{0};
  std::atomic<uint64_t> done_{0};
  std::atomic<bool> quit_{false};
  int worker_row_begin_ = 0, worker_row_end_ = 0;
};

}  // namespace hd::render::lens
