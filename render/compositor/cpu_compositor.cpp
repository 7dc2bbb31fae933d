#include "render/compositor/cpu_compositor.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/compositor/border_weight.h"
#include "render/compositor/packed_rgba.h"
#include "render/compositor/request_check.h"

namespace hd::render {

namespace {

const SyntheticScene& empty_scene() {
  static const SyntheticScene scene;
  return scene;
}

}  // namespace

CpuCompositor::CpuCompositor(int threads) : threads_(std::clamp(threads, 1, 2)) {
  if (threads_ == 2) worker_ = std::thread([this] { worker_loop(); });
}

CpuCompositor::~CpuCompositor() {
  if (worker_.joinable()) {
    quit_.store(true);
    job_.fetch_add(1);
    job_.notify_one();
    worker_.join();
  }
}

void CpuCompositor::worker_loop() {
  uint64_t seen = 0;
  for (;;) {
    job_.wait(seen);
    seen = job_.load();
    if (quit_.load()) return;
    draw_band(worker_row_begin_, worker_row_end_);
    done_.store(seen);
    done_.notify_one();
  }
}

void CpuCompositor::draw(const CompositeRequest& req, ImageRgba8& out) {
  if (!request_drawable(req, out)) {
    ++stats_.requests_rejected;
    return;
  }
  const std::size_t n = static_cast<std::size_t>(req.viewport.width) * req.viewport.height;
  if (inv_depth_.size() != n) {  // first frame, or a new viewport size
    inv_depth_.assign(n, 0.0f);
    synth_rgba_.assign(4 * n, 0);
    scratch_.assign(2 * 3 * static_cast<std::size_t>(req.viewport.width), 0.0f);
  }
  req_ = &req;
  out_ = &out;
  scene_ = req.scene ? req.scene : &empty_scene();
  video_on_ = false;
  if (req.video != nullptr && req.has_region) {
    if (video_usable(req)) {
      warp_ = VideoWarp::make(req.eye, req.T_world_eye, req.real, req.T_world_real, req.d_m);
      video_on_ = warp_.usable;
    } else {
      ++stats_.video_frames_rejected;
    }
  }
  rasterizer_.prepare(*scene_, req.eye, req.T_world_eye, req.near_m, req.far_m);

  const int h = req.viewport.height;
  if (threads_ == 2 && h >= 2) {
    worker_row_begin_ = h / 2;
    worker_row_end_ = h;
    const uint64_t my_job = job_.fetch_add(1) + 1;
    job_.notify_one();
    draw_band(0, h / 2);
    for (uint64_t d = done_.load(); d != my_job; d = done_.load()) done_.wait(d);
  } else {
    draw_band(0, h);
  }
  ++stats_.frames_drawn;
  req_ = nullptr;
  out_ = nullptr;
}

void CpuCompositor::draw_band(int row_begin, int row_end) {
  const CompositeRequest& req = *req_;
  const int W = req.viewport.width;
  std::fill(inv_depth_.begin() + static_cast<long>(row_begin) * W,
            inv_depth_.begin() + static_cast<long>(row_end) * W, 0.0f);
  const RasterTarget target{synth_rgba_.data(), inv_depth_.data(), W, req.viewport.height};
  rasterizer_.draw_rows(*scene_, target, row_begin, row_end);

  const core::MarkingParams mark = req.marking.sanitized();
  const bool desaturate = mark.style == core::MarkingStyle::kDesaturate;
  const bool checker = mark.style == core::MarkingStyle::kChecker;
  const float desat = static_cast<float>(mark.synthetic_desaturation);
  const float checker_step = static_cast<float>(0.5 * mark.checker_contrast * 255.0);
  const int cell = mark.checker_cell_px;
  const float bg[3] = {static_cast<float>(scene_->background_rgb[0]),
                       static_cast<float>(scene_->background_rgb[1]),
                       static_cast<float>(scene_->background_rgb[2])};

  // Video weight: the global one, or per pixel the continuous w2 of core (DESIGN 7).
  const double w_video =
      std::isnan(req.transition.w_video) ? 0.0 : std::clamp(req.transition.w_video, 0.0, 1.0);
  const bool per_pixel = req.mode == core::TransitionMode::kPerPixel;
  const bool any_video =
      video_on_ && (per_pixel ? std::min(1.0, 2.0 * w_video) > 0.0 : w_video > 0.0);

  const drivers::Frame* vf = req.video;
  const int vw = any_video ? vf->width : 0;
  const int vh = any_video ? vf->height : 0;
  const double vwd = vw, vhd = vh;
  const uint8_t* vdata = any_video ? vf->data.data() : nullptr;
  const int vstride = any_video ? vf->stride_bytes : 0;
  const bool nearest = req.sampling == VideoSampling::kNearest;
  const double inv_near = 1.0 / req.near_m;
  const Eigen::Matrix3d& H = warp_.H;
  // core::continuous_pixel_weight without its per-pixel call, divisions and sin (a table).
  const BorderWeight border(w_video, std::max(vwd, 1.0), std::max(vhd, 1.0));

  const Eigen::Vector3d& q = warp_.inv_depth;

  // Per-thread row scratch: where each pixel samples the frame and with what weight.
  float* su = scratch_.data() + (row_begin == 0 ? 0 : 3 * static_cast<std::size_t>(W));
  float* sv = su + W;
  float* sa = sv + W;
  const float wv = static_cast<float>(w_video);
  const uint8_t bg_rgba[4] = {scene_->background_rgb[0], scene_->background_rgb[1],
                              scene_->background_rgb[2], 255};

  for (int y = row_begin; y < row_end; ++y) {
    const uint8_t* srow = synth_rgba_.data() + static_cast<long>(y) * W * 4;
    const float* drow = inv_depth_.data() + static_cast<long>(y) * W;
    uint8_t* orow = out_->pixel(req.viewport.x, req.viewport.y + y);
    if (any_video) {
      // Pass A (branch-free, so the compiler vectorises it): the homography at every pixel
      // centre of the row, the in-front and inside-the-frame tests.
      const double pv = y + 0.5;
      const double bx = H(0, 1) * pv + H(0, 2), by = H(1, 1) * pv + H(1, 2);
      const double bw = H(2, 1) * pv + H(2, 2), bz = q(1) * pv + q(2);
      const double h00 = H(0, 0), h10 = H(1, 0), h20 = H(2, 0), q0 = q(0);
      for (int x = 0; x < W; ++x) {
        const double px = x + 0.5;
        const double iz = q0 * px + bz;
        const double inv_hw = 1.0 / (h20 * px + bw);
        const double u = (h00 * px + bx) * inv_hw;
        const double w = (h10 * px + by) * inv_hw;
        const bool in = iz > 0.0 && iz <= inv_near && u >= 0.0 && u <= vwd && w >= 0.0 && w <= vhd;
        su[x] = in ? static_cast<float>(u) : 0.0f;
        sv[x] = in ? static_cast<float>(w) : 0.0f;
        sa[x] = in ? wv : 0.0f;
      }
      if (per_pixel) {
        for (int x = 0; x < W; ++x) {
          if (sa[x] > 0.0f) sa[x] = border(su[x], sv[x]);
        }
      }
    }
    const int checker_row = y / cell;
    for (int x = 0; x < W; ++x) {
      const float a = any_video ? sa[x] : 0.0f;
      uint8_t* o = orow + 4 * x;
      uint32_t video = 0;  // RGBA bytes, little-endian packed
      if (a > 0.0f) {
        const float u = su[x], w = sv[x];
        if (nearest) {
          const int xi = std::min(static_cast<int>(u), vw - 1);
          const int yi = std::min(static_cast<int>(w), vh - 1);
          std::memcpy(&video, vdata + static_cast<long>(yi) * vstride + 4 * xi, 4);
        } else {
          // 8-bit fixed-point bilinear between texel centres, clamped to the edge texels; two
          // channels per multiply. Rounding (not truncating) to 1/256 px keeps an exact texel
          // centre exact; u, w >= 0, so the +256 offset keeps the truncated value positive.
          const int X = static_cast<int>(u * 256.0f + (256.0f - 128.0f + 0.5f)) - 256;
          const int Y = static_cast<int>(w * 256.0f + (256.0f - 128.0f + 0.5f)) - 256;
          const int x0 = X >> 8, fx = X & 255;  // arithmetic shift: floor, also below 0
          const int y0 = Y >> 8, fy = Y & 255;
          if (static_cast<unsigned>(x0) < static_cast<unsigned>(vw - 1) &&
              static_cast<unsigned>(y0) < static_cast<unsigned>(vh - 1)) {
            // All four texels inside (nearly every pixel): no clamping.
            video =
                bilinear_rgba(vdata + static_cast<long>(y0) * vstride + 4 * x0, vstride, fx, fy);
          } else {
            const int xa = std::max(x0, 0), xb = std::min(x0 + 1, vw - 1);
            const int ya = std::max(y0, 0), yb = std::min(y0 + 1, vh - 1);
            const uint8_t* r0 = vdata + static_cast<long>(ya) * vstride;
            const uint8_t* r1 = vdata + static_cast<long>(yb) * vstride;
            uint32_t c00, c10, c01, c11;
            std::memcpy(&c00, r0 + 4 * xa, 4);
            std::memcpy(&c10, r0 + 4 * xb, 4);
            std::memcpy(&c01, r1 + 4 * xa, 4);
            std::memcpy(&c11, r1 + 4 * xb, 4);
            video = lerp_rgba(lerp_rgba(c00, c10, fx), lerp_rgba(c01, c11, fx), fy);
          }
        }
        if (a >= 1.0f) {  // pure video: no need for the model's colour
          video |= 0xFF000000u;
          std::memcpy(o, &video, 4);
          continue;
        }
      }
      if (a <= 0.0f && !desaturate && !checker) {  // the model as drawn (or the background)
        if (drow[x] > 0.0f) {
          std::memcpy(o, srow + 4 * x, 4);
        } else {
          std::memcpy(o, bg_rgba, 4);
        }
        o[3] = 255;
        continue;
      }
      float s[3];
      if (drow[x] > 0.0f) {
        for (int c = 0; c < 3; ++c) s[c] = srow[4 * x + c];
      } else {
        for (int c = 0; c < 3; ++c) s[c] = bg[c];
      }
      if (desaturate) {
        const float grey = 0.299f * s[0] + 0.587f * s[1] + 0.114f * s[2];
        for (int c = 0; c < 3; ++c) s[c] += desat * (grey - s[c]);
      } else if (checker) {
        const float step = ((x / cell + checker_row) & 1) ? -checker_step : checker_step;
        for (int c = 0; c < 3; ++c) s[c] = std::clamp(s[c] + step, 0.0f, 255.0f);
      }
      for (int c = 0; c < 3; ++c) {
        const float v = static_cast<float>((video >> (8 * c)) & 255u);
        const float val = s[c] + a * (v - s[c]);
        o[c] = static_cast<uint8_t>(std::clamp(val, 0.0f, 255.0f) + 0.5f);
      }
      o[3] = 255;
    }
    // The variant's coloured frame is painted last, over video and model alike.
    if (mark.style == core::MarkingStyle::kFrame && mark.frame_width_px > 0) {
      const core::Rgb& fc = mark.frame_colour(req.transition.variant);
      const int fw = mark.frame_width_px;
      const int H_vp = req.viewport.height;
      const bool full_row = y < fw || y >= H_vp - fw;
      for (int x = 0; x < W; ++x) {
        if (full_row || x < fw || x >= W - fw) {
          uint8_t* o = orow + 4 * x;
          o[0] = fc.r;
          o[1] = fc.g;
          o[2] = fc.b;
        }
        if (!full_row && x == fw - 1 && W - fw > x + 1) x = W - fw - 1;  // skip the middle
      }
    }
  }
}

}  // namespace hd::render
