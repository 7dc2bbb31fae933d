#pragma once
// The CPU pre-distortion pass: both eyes warped through the inverse lens model into the panel.
// The sampler every row kernel matches is lens_sampler.h; the SIMD row kernels are
// predistort_kernels.h.

#include <cstdint>
#include <vector>

#include "render/compositor/image_rgba8.h"
#include "render/cpu/row_worker.h"
#include "render/lens/lens_warp.h"

namespace hd::render::lens {

/// Fills the HMD panel's picture from the eyes' picture (the StereoRig layout: two eye images of
/// warp.eye_width() x warp.eye_height() side by side). Each panel pixel takes R, G and B from
/// the eye image at the points LensWarp::source gives for its centre, sampled bilinearly with
/// 8-bit fixed-point weights on a 1/256 px grid (the CPU compositor's sampler; clamped to the
/// pixel's own eye image); alpha is 255, and pixels beyond the usable lens radius are opaque
/// black. Per row and eye the span of usable pixels is found once in the constructor.
///
/// Two ways to find the sample points (Method), each with a scalar and an AVX2 row kernel that
/// give the same bytes:
///  - kRadial (default): evaluated per pixel in single precision from the lens radius
///    (LensWarp::panel_map: a square root and the ratio polynomial by Horner, then one
///    multiply-add per channel and axis), so no per-pixel table is read; the AVX2 kernel fetches
///    each pair of horizontally adjacent texels with one 64-bit gather lane and weighs them with
///    pmaddwd. Compute, not memory, bounds this pass (the profile in docs/hmd.md).
///  - kPositionTable (the first version, kept for the benchmark): a table of the green sample's
///    position in 1/256 px (two int32 per panel pixel, 7.7 MB for 1600x600); R and B are the green
///    offset from the eye's principal point scaled by aberration[c] / aberration[G] in 16.16
///    fixed point.
///
/// apply() allocates nothing; with N threads the caller and N - 1 persistent workers (woken
/// through an atomic) claim rows four at a time from a shared counter (RowWorker's kClaimed), so
/// the work splits evenly whatever the rows cost and however late a worker wakes (or, on a busy
/// machine, the caller does them all); the caller spins briefly for the last rows before it
/// sleeps on the atomic. `threads` in 1..RowWorker::kMaxThreads, else std::invalid_argument.
class CpuPredistorter {
 public:
  enum class Method { kRadial, kPositionTable };
  /// Row kernels, all giving the same bytes: kBest takes the widest the CPU has (kRadial has an
  /// AVX-512 F/BW/VBMI one, both methods an AVX2 + FMA one), kAvx2 at most AVX2, kNone scalar.
  enum class Simd { kNone, kAvx2, kAvx512, kBest };

  CpuPredistorter(const LensWarp& warp, int threads = 1, Simd simd = Simd::kBest,
                  Method method = Method::kRadial);
  ~CpuPredistorter();
  CpuPredistorter(const CpuPredistorter&) = delete;
  CpuPredistorter& operator=(const CpuPredistorter&) = delete;

  /// `eyes` must be at least 2 * eye_width x eye_height, `panel` allocated to the panel's size;
  /// false (nothing written) otherwise.
  bool apply(const ImageRgba8& eyes, ImageRgba8& panel);

  /// The same picture with every sample point evaluated from the lens polynomial per pixel and
  /// channel (double precision): the reference the benchmark and the tests compare against.
  bool apply_exact(const ImageRgba8& eyes, ImageRgba8& panel) const;

  /// Where apply() samples channel c for the usable panel pixel (x, y) of eye e's half, in eye
  /// e's own image coordinates, before the sampler's 1/256 px grid: for the benchmark's
  /// geometric error against LensWarp::source.
  void sample_point(int eye, int x, int y, int channel, double* u, double* v) const;

  const LensWarp& warp() const { return warp_; }
  Method method() const { return method_; }
  /// The row kernel in use (kNone, kAvx2 or kAvx512).
  Simd simd() const { return simd_; }
  /// How many (row, eye) spans run the kernels without the clamp (kRadial; for the tests).
  int clamp_free_spans() const;

 private:
  struct Span {
    int begin = 0, end = 0;   ///< usable panel columns [begin, end) of one eye in one row
    bool clamp_free = false;  ///< kRadial: no sample point of the kernels' groups needs the clamp
  };
  /// kRadial's constants of one eye, single precision (the kernels' arithmetic):
  /// d = float(column in the half) + d0, r = sqrt(fma(d.x k.x, d.x k.x, (d.y k.y)^2)),
  /// t = ratio(r), and channel c's fixed-point point is trunc(fma(t d, gain256[c], origin256)).
  struct RadialEye {
    float d0[2] = {};          ///< 0.5 - lens centre (panel px)
    float k[2] = {};           ///< r units per panel px
    float gain256[3][2] = {};  ///< 256 * LensWarp::PanelMap::gain
    float origin256[2] = {};   ///< 256 * (principal point + eye offset - 0.5)
  };
  static constexpr int kMaxRatioTerms = 11;  ///< HmdProfile allows 12 coefficients

  void band(int row_begin, int row_end);
  /// kRadial's fixed-point sample points (before truncation) of half column x_half, channels
  /// R, G, B: the arithmetic of every kernel.
  void radial_points(int y, int eye, int x_half, float* X, float* Y) const;
  void radial_span_scalar(int y, int eye, int x, int end, uint32_t* out) const;
  void table_span_scalar(int y, int eye, int x, int end, uint32_t* out) const;
  static constexpr int kRowsPerTake = 4;  ///< rows a thread claims at a time

  LensWarp warp_;
  Method method_ = Method::kRadial;
  std::vector<Span> spans_;  ///< [row * 2 + eye]

  RadialEye radial_[2];
  float ratio_[kMaxRatioTerms] = {};  ///< ratio(r) = sum ratio_[i] r^i (coefficients[i + 1])
  int ratio_terms_ = 0;

  /// kPositionTable: per panel pixel the green sample in the eyes' picture, 256 * (u - 0.5, v -
  /// 0.5); empty for kRadial.
  std::vector<int32_t> positions_;
  int32_t scale_fixed_[3] = {65536, 65536, 65536};  ///< channel_scale * 2^16
  int32_t centre_fixed_[2][2] = {};                 ///< principal points, as positions_

  const ImageRgba8* eyes_ = nullptr;  ///< valid during apply only
  ImageRgba8* panel_ = nullptr;

  Simd simd_ = Simd::kNone;
  int threads_ = 1;
  RowWorker rows_;  ///< last: its thread stops before the members it draws with go
};

}  // namespace hd::render::lens
