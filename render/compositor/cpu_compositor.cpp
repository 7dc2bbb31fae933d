#include "render/compositor/cpu_compositor.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "render/compositor/border_weight.h"
#include "render/compositor/depth_warp.h"
#include "render/compositor/packed_rgba.h"
#include "render/compositor/request_check.h"
#include "render/compositor/row_kernels.h"

namespace hd::render {

namespace {

// X = round(u * 256 - 128) as floor(u * 256 + 128.5) - 256 (u >= 0), likewise Y: the texel
// grid position in 1/256 px, for the bilinear sample.
void fixed_point_positions(int n, const float* u, const float* v, int* X, int* Y) {
  int x = 0;
#if defined(__SSE2__)
  const __m128 scale = _mm_set1_ps(256.0f), offset = _mm_set1_ps(256.0f - 128.0f + 0.5f);
  const __m128i shift = _mm_set1_epi32(256);
  for (; x + 4 <= n; x += 4) {
    const __m128i fx = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(u + x), scale), offset));
    const __m128i fy = _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(v + x), scale), offset));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(X + x), _mm_sub_epi32(fx, shift));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(Y + x), _mm_sub_epi32(fy, shift));
  }
#endif
  for (; x < n; ++x) {
    X[x] = static_cast<int>(u[x] * 256.0f + (256.0f - 128.0f + 0.5f)) - 256;
    Y[x] = static_cast<int>(v[x] * 256.0f + (256.0f - 128.0f + 0.5f)) - 256;
  }
}

// The video is sampled in tiles of kRowGroup rows by kTilePx columns (after the positions of
// all kRowGroup rows are known). A warp that turns the frame walks it across its rows: one whole
// eye row touches a diagonal strip of texel cache lines too large for L1, and the next eye row
// reuses most of those lines; a tile's strips stay in L1 between its rows.
constexpr int kRowGroup = 8;
constexpr int kTilePx = 64;

const SyntheticScene& empty_scene() {
  static const SyntheticScene scene;
  return scene;
}

}  // namespace

CpuCompositor::CpuCompositor(int threads)
    : threads_(threads), rows_(threads, RowWorker::Split::kBands) {}

CpuCompositor::~CpuCompositor() = default;

void CpuCompositor::set_lens(const lens::LensWarp* warp) {
  lens_.reset();
  if (warp) lens_ = std::make_unique<lens::CpuPredistorter>(*warp, threads_);
}

void CpuCompositor::predistort(const ImageRgba8& eyes, ImageRgba8& panel) {
  if (lens_ && !lens_->apply(eyes, panel)) ++stats_.requests_rejected;
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
    const std::size_t group = kRowGroup * static_cast<std::size_t>(req.viewport.width);
    const auto bands = static_cast<std::size_t>(threads_);
    scratch_.assign(bands * 4 * group, 0.0f);
    video_row_.assign(bands * group, 0u);
    fixed_.assign(bands * 2 * group, 0);
  }
  req_ = &req;
  out_ = &out;
  const std::size_t picture = static_cast<std::size_t>(out.width) * out.height;
  if (weight_map_ != nullptr && weight_map_->size() != picture) weight_map_->assign(picture, 0);
  if (model_only_ != nullptr &&
      (model_only_->width != out.width || model_only_->height != out.height))
    model_only_->allocate(out.width, out.height);
  if (position_map_ != nullptr && position_map_->size() != 2 * picture)
    position_map_->assign(2 * picture, NAN);
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
  depth_view_ = false;
  if (video_on_ && req.video_view == core::VideoView::kModelDepth) {
    depth_warp_ = DepthWarp::make(req.eye, req.T_world_eye, req.real, req.T_world_real);
    if (depth_warp_.usable) {
      if (camera_depth_.update(*scene_, req.real, req.T_world_real, req.near_m, req.far_m, &rows_))
        ++stats_.camera_depth_renders;
      depth_view_ = true;
    }
  }
  rasterizer_.prepare(*scene_, req.eye, req.T_world_eye, req.near_m, req.far_m);

  auto band = [this](int row_begin, int row_end, int thread) {
    draw_band(row_begin, row_end, thread);
  };
  rows_.run(req.viewport.height, band);
  ++stats_.frames_drawn;
  req_ = nullptr;
  out_ = nullptr;
}

void CpuCompositor::record_positions(int y, const float* u, const float* v, const float* a) {
  const CompositeRequest& req = *req_;
  float* p =
      position_map_->data() + 2 * (static_cast<std::size_t>(req.viewport.y + y) * out_->width +
                                   static_cast<std::size_t>(req.viewport.x));
  for (int x = 0; x < req.viewport.width; ++x) {
    const bool sees = a != nullptr && a[x] > 0.0f;
    p[2 * x] = sees ? u[x] : NAN;
    p[2 * x + 1] = sees ? v[x] : NAN;
  }
}

void CpuCompositor::draw_band(int row_begin, int row_end, int band_index) {
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
  // The model-depth view: the same rows with the eye's model depth in place of the plane's.
  const Eigen::Matrix3d& A = depth_warp_.A;
  DepthRow dr;
  if (depth_view_) {
    dr.a00 = A(0, 0);
    dr.a10 = A(1, 0);
    dr.a20 = A(2, 0);
    dr.b0 = depth_warp_.b(0);
    dr.b1 = depth_warp_.b(1);
    dr.b2 = depth_warp_.b(2);
    dr.q0 = q(0);
    dr.inv_near = inv_near;
    dr.width = vwd;
    dr.height = vhd;
    dr.weight = static_cast<float>(w_video);
    dr.seen = camera_depth_.data();
    dr.seen_width = camera_depth_.width();
    dr.seen_height = camera_depth_.height();
  }

  // Per-thread scratch for kRowGroup rows: where each pixel samples the frame, with what weight,
  // the 1/256 px texel positions and the texel.
  const std::size_t band = static_cast<std::size_t>(band_index);
  const std::size_t group = kRowGroup * static_cast<std::size_t>(W);
  float* su_group = scratch_.data() + band * 4 * group;
  float* sv_group = su_group + group;
  float* sa_group = sv_group + group;
  float* sz_group = sa_group + group;  // model-depth: 1 / z_real awaiting the seen test
  uint32_t* vid_group = video_row_.data() + band * group;
  int* fx_group = fixed_.data() + band * 2 * group;
  int* fy_group = fx_group + group;
  const float wv = static_cast<float>(w_video);

  RowBlend blend;
  blend.background = static_cast<uint32_t>(scene_->background_rgb[0]) |
                     static_cast<uint32_t>(scene_->background_rgb[1]) << 8 |
                     static_cast<uint32_t>(scene_->background_rgb[2]) << 16 | 0xFF000000u;
  blend.desaturate = desaturate;
  blend.desaturation = desat;
  blend.checker = checker;
  blend.checker_step = checker_step;
  blend.checker_cell_px = cell;
  blend.fade = static_cast<float>(mark.synthetic_fade);
  if (!any_video) std::fill(vid_group, vid_group + group, 0u);

  RowWarp rw;
  rw.h00 = H(0, 0);
  rw.h10 = H(1, 0);
  rw.h20 = H(2, 0);
  rw.q0 = q(0);
  rw.inv_near = inv_near;
  rw.width = vwd;
  rw.height = vhd;
  rw.weight = wv;

  // The texel pixel x of a row with positions (su, sv, weight sa, fixed point X, Y) blends in
  // (0 where sa = 0: a = 0 ignores it).
  const auto sample_nearest = [&](const float* su, const float* sv, const float* sa, uint32_t* vid,
                                  int x_begin, int x_end) {
    for (int x = x_begin; x < x_end; ++x) {
      if (!(sa[x] > 0.0f)) {
        vid[x] = 0;
        continue;
      }
      const int xi = std::min(static_cast<int>(su[x]), vw - 1);
      const int yi = std::min(static_cast<int>(sv[x]), vh - 1);
      std::memcpy(vid + x, vdata + static_cast<long>(yi) * vstride + 4 * xi, 4);
    }
  };
  // 8-bit fixed-point bilinear between texel centres, clamped to the edge texels.
  const auto sample_bilinear = [&](const int* fixed_x, const int* fixed_y, const float* sa,
                                   uint32_t* vid, int x_begin, int x_end) {
    for (int x = x_begin; x < x_end; ++x) {
      if (!(sa[x] > 0.0f)) {
        vid[x] = 0;
        continue;
      }
      const int X = fixed_x[x];
      const int Y = fixed_y[x];
      const int x0 = X >> 8, fx = X & 255;  // arithmetic shift: floor, also below 0
      const int y0 = Y >> 8, fy = Y & 255;
      if (static_cast<unsigned>(x0) < static_cast<unsigned>(vw - 1) &&
          static_cast<unsigned>(y0) < static_cast<unsigned>(vh - 1)) {
        // All four texels inside (nearly every pixel): no clamping.
        vid[x] = bilinear_rgba(vdata + static_cast<long>(y0) * vstride + 4 * x0, vstride, fx, fy);
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
        vid[x] = lerp_rgba(lerp_rgba(c00, c10, fx), lerp_rgba(c01, c11, fx), fy);
      }
    }
  };

  for (int y_group = row_begin; y_group < row_end; y_group += kRowGroup) {
    const int rows = std::min(kRowGroup, row_end - y_group);
    if (any_video) {
      // Where each pixel centre of the rows meets the frame, and whether it sees it at all.
      for (int r = 0; r < rows; ++r) {
        const double pv = y_group + r + 0.5;
        const std::size_t off = static_cast<std::size_t>(r) * W;
        if (depth_view_) {
          dr.cx = A(0, 1) * pv + A(0, 2);
          dr.cy = A(1, 1) * pv + A(1, 2);
          dr.cw = A(2, 1) * pv + A(2, 2);
          dr.bz = q(1) * pv + q(2);
          depth_warp_row(dr, W, inv_depth_.data() + static_cast<long>(y_group + r) * W,
                         su_group + off, sv_group + off, sa_group + off, sz_group + off);
        } else {
          rw.bx = H(0, 1) * pv + H(0, 2);
          rw.by = H(1, 1) * pv + H(1, 2);
          rw.bw = H(2, 1) * pv + H(2, 2);
          rw.bz = q(1) * pv + q(2);
          warp_row(rw, W, su_group + off, sv_group + off, sa_group + off);
        }
      }
      if (depth_view_) {
        for (int x_begin = 0; x_begin < W; x_begin += kTilePx) {
          const int x_end = std::min(W, x_begin + kTilePx);
          for (int r = 0; r < rows; ++r) {
            const std::size_t off = static_cast<std::size_t>(r) * W;
            seen_test_row(dr, x_begin, x_end, su_group + off, sv_group + off, sz_group + off,
                          sa_group + off);
          }
        }
      }
      for (int r = 0; r < rows; ++r) {
        const std::size_t off = static_cast<std::size_t>(r) * W;
        if (position_map_ != nullptr)
          record_positions(y_group + r, su_group + off, sv_group + off, sa_group + off);
        if (per_pixel) border.apply_row(W, su_group + off, sv_group + off, sa_group + off);
        // Rounding (not truncating) to 1/256 px keeps an exact texel centre exact; u, v >= 0,
        // so the +256 offset keeps the truncated value positive.
        if (!nearest) {
          fixed_point_positions(W, su_group + off, sv_group + off, fx_group + off, fy_group + off);
        }
      }
      for (int x_begin = 0; x_begin < W; x_begin += kTilePx) {
        const int x_end = std::min(W, x_begin + kTilePx);
        for (int r = 0; r < rows; ++r) {
          const std::size_t off = static_cast<std::size_t>(r) * W;
          if (nearest) {
            sample_nearest(su_group + off, sv_group + off, sa_group + off, vid_group + off, x_begin,
                           x_end);
          } else {
            sample_bilinear(fx_group + off, fy_group + off, sa_group + off, vid_group + off,
                            x_begin, x_end);
          }
        }
      }
    }
    for (int r = 0; r < rows; ++r) {
      const int y = y_group + r;
      const std::size_t off = any_video ? static_cast<std::size_t>(r) * W : 0;
      const float* sa = sa_group + off;
      const uint32_t* vid = vid_group + off;
      const uint8_t* srow = synth_rgba_.data() + static_cast<long>(y) * W * 4;
      const float* drow = inv_depth_.data() + static_cast<long>(y) * W;
      uint8_t* orow = out_->pixel(req.viewport.x, req.viewport.y + y);
      // out = s + a (v - s) with the marked model colour s, four pixels at a time.
      blend.checker_row = y / cell;
      blend_row_sse2(blend, 0, W, srow, drow, any_video ? sa : nullptr, vid, orow);
      if (model_only_ != nullptr)
        blend_row_sse2(blend, 0, W, srow, drow, nullptr, vid,
                       model_only_->pixel(req.viewport.x, req.viewport.y + y));
      if (position_map_ != nullptr && !any_video) record_positions(y, nullptr, nullptr, nullptr);
      if (weight_map_ != nullptr) {
        uint8_t* wrow = weight_map_->data() +
                        static_cast<std::size_t>(req.viewport.y + y) * out_->width +
                        static_cast<std::size_t>(req.viewport.x);
        for (int x = 0; x < W; ++x)
          wrow[x] = any_video && sa[x] > 0.0f
                        ? static_cast<uint8_t>(255.0f * std::min(sa[x], 1.0f) + 0.5f)
                        : 0;
      }
      // The variant's coloured frame is painted last, over video and model alike.
      // Video past its age bound recolours the frame (and draws one in every other style).
      const bool stale = mark.video_stale && mark.style != core::MarkingStyle::kNone;
      if ((mark.style == core::MarkingStyle::kFrame || stale) && mark.frame_width_px > 0) {
        const core::Rgb& fc = stale ? mark.stale_rgb : mark.frame_colour(req.transition.variant);
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
}

}  // namespace hd::render
