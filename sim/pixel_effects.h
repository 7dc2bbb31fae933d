#pragma once
// The frame effects that change pixels after the render: lens distortion, exposure, sensor noise.
// Each is built only when the scene lists it; apply() works in place on a sized frame and does not
// allocate.

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>

#include "core/pinhole.h"
#include "drivers/frame.h"
#include "render/compositor/image_rgba8.h"
#include "sim/scene/scene.h"

namespace hd::sim {

/// Gaussian noise per colour channel, sigma in digital numbers, zero mean; rounded and clipped to
/// 0..255. Each draw is the sum of four 16-bit uniforms (Irwin-Hall, exact mean and variance,
/// tails cut at 3.46 sigma) from a per-frame generator seeded by (seed, camera, sequence).
class SensorNoise {
 public:
  SensorNoise(const SensorNoiseEffect& effect, uint64_t camera_stream);
  void apply(drivers::Frame& frame) const;  ///< uses frame.sequence

 private:
  SensorNoiseEffect effect_;
  uint64_t stream_;
};

/// out = clip(round(gain * in + offset)) on R, G, B through a 256-entry table.
class ExposureLut {
 public:
  explicit ExposureLut(const ExposureEffect& effect);
  void apply(drivers::Frame& frame) const;
  uint8_t operator()(uint8_t in) const { return lut_[in]; }

 private:
  std::array<uint8_t, 256> lut_{};
};

/// Makes the ideal pinhole render look as the real lens would: the distorted image's pixel centre
/// (u, v) (continuous coordinates, DESIGN.md) shows the ideal image at the undistorted point of
/// (u, v) under OpenCV's model with the camera's K and coefficients (the inverse of what the
/// station's undistorter does). Maps are computed once (cv::undistortPoints, iterated to 1e-6 px)
/// and applied with cv::remap, bilinear, border = the background of the edge pixel.
class LensDistorter {
 public:
  explicit LensDistorter(const core::Pinhole& camera);
  void apply(const render::ImageRgba8& ideal, drivers::Frame& out) const;

 private:
  cv::Mat map1_, map2_;  ///< fixed-point maps from cv::convertMaps
};

}  // namespace hd::sim
