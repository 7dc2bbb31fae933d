#include "sim/sim_camera_renderer.h"

#include <algorithm>

#include "sim/simulation.h"

namespace hd::sim {

SimCameraRenderer::SimCameraRenderer(const Simulation& sim, std::size_t camera_index)
    : sim_(sim), scene_(sim.model()) {
  const Scene& s = sim.scene();
  const SceneCamera& cam = s.cameras.at(camera_index);
  ideal_ = cam.p_c;
  ideal_.distortion = {};
  ideal_.distortion_count = 0;
  T_world_cam_ = cam.T_world_cam;
  image_.allocate(ideal_.width, ideal_.height);
  const SceneEffects& fx = s.effects;
  blur_ = fx.motion_blur;
  rolling_ = fx.rolling_shutter;
  if (blur_) accum_.assign(image_.data.size(), 0);
  if (fx.lens_distortion) distorter_ = std::make_unique<LensDistorter>(cam.p_c);
  if (fx.exposure) exposure_.emplace(*fx.exposure);
  if (fx.sensor_noise) noise_.emplace(*fx.sensor_noise, camera_index);
}

void SimCameraRenderer::draw_rows(double t_s, int row_begin, int row_end) {
  sim_.place_objects(scene_, t_s);
  render::CompositeRequest req;
  req.scene = &scene_;
  req.eye = ideal_;
  req.eye.cy -= row_begin;  // the band's own pinhole: same rays, fewer rows
  req.eye.height = row_end - row_begin;
  req.T_world_eye = T_world_cam_;
  req.marking.style = core::MarkingStyle::kNone;
  req.viewport = {0, row_begin, ideal_.width, row_end - row_begin};
  compositor_.draw(req, image_);
}

void SimCameraRenderer::render(drivers::Frame& frame, double t_s) {
  const int h = ideal_.height;
  if (!blur_ && !rolling_) {
    draw_rows(t_s, 0, h);
  } else {
    const int bands = rolling_ ? std::min(rolling_->bands, h) : 1;
    const int samples = blur_ ? blur_->samples : 1;
    const double line_s = rolling_ ? rolling_->readout_ms * 1e-3 / h : 0.0;
    const std::size_t row_bytes = static_cast<std::size_t>(image_.stride_bytes);
    for (int b = 0; b < bands; ++b) {
      const int r0 = h * b / bands;
      const int r1 = h * (b + 1) / bands;
      if (r1 <= r0) continue;
      const double t_band = t_s + line_s * 0.5 * (r0 + r1);  // the band's middle row
      for (int k = 0; k < samples; ++k) {
        const double t_k =
            blur_ ? t_band + blur_->exposure_ms * 1e-3 * (k + 0.5) / samples : t_band;
        draw_rows(t_k, r0, r1);
        if (!blur_) continue;
        const std::size_t begin = static_cast<std::size_t>(r0) * row_bytes;
        const std::size_t end = static_cast<std::size_t>(r1) * row_bytes;
        if (k == 0) {
          std::copy(image_.data.begin() + static_cast<std::ptrdiff_t>(begin),
                    image_.data.begin() + static_cast<std::ptrdiff_t>(end),
                    accum_.begin() + static_cast<std::ptrdiff_t>(begin));
        } else {
          for (std::size_t i = begin; i < end; ++i)
            accum_[i] = static_cast<uint16_t>(accum_[i] + image_.data[i]);
        }
      }
      if (blur_) {
        const std::size_t begin = static_cast<std::size_t>(r0) * row_bytes;
        const std::size_t end = static_cast<std::size_t>(r1) * row_bytes;
        const unsigned n = static_cast<unsigned>(samples);
        for (std::size_t i = begin; i < end; ++i) {
          image_.data[i] = static_cast<uint8_t>((accum_[i] + n / 2) / n);
        }
      }
    }
  }
  if (frame.width != ideal_.width || frame.height != ideal_.height ||
      frame.format != drivers::PixelFormat::kRgba8 || frame.stride_bytes != image_.stride_bytes ||
      frame.data.size() != image_.data.size()) {
    frame.allocate_rgba(ideal_.width, ideal_.height);
  }
  if (distorter_) {
    distorter_->apply(image_, frame);
  } else {
    frame.data.swap(image_.data);  // same size: the next render reuses the old frame buffer
  }
  if (exposure_) exposure_->apply(frame);
  if (noise_) noise_->apply(frame);
}

}  // namespace hd::sim
