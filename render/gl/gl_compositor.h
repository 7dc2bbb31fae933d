#pragma once
// The OpenGL 3.3 core compositor: the CPU reference's picture, drawn by shaders.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "render/compositor/compositor.h"
#include "render/gl/gl_objects.h"
#include "render/gl/gl_window.h"
#include "render/overlay/overlay_geometry.h"

namespace hd::render {

/// Draws CompositeRequest's picture (see composite_request.h) with two passes into an offscreen
/// framebuffer the size of `out`: the meshes with a depth buffer, then one full-screen pass that
/// evaluates the plane homography per fragment, samples the video bilinearly (GL_LINEAR,
/// clamp-to-edge, texel centres at +0.5, no sRGB), computes the continuous w2, blends over the
/// synthetic colour and paints the marks. Framebuffer row r is picture row r (y down), so a
/// read-back needs no flip; present() blits it upright to the window.
///
/// Uploads: the scene's meshes and textures when the scene pointer or its revision changes; the
/// video only inside the request's update region (grown to whole pixels plus one pixel for the
/// bilinear neighbours) with GL_UNPACK_ROW_LENGTH / SKIP_PIXELS / SKIP_ROWS, and only when the
/// frame (pointer, sequence, host time) or the region changed since the last upload — so the
/// second eye of a stereo pair re-uses the first eye's upload.
///
/// Construction makes the window and context (throws std::runtime_error with the reason if no
/// 3.3 core context can be had); draw/present must run on the thread that constructed it.
class GlCompositor final : public Compositor {
 public:
  explicit GlCompositor(const gl::WindowOptions& options);
  ~GlCompositor() override;
  GlCompositor(const GlCompositor&) = delete;
  GlCompositor& operator=(const GlCompositor&) = delete;

  void draw(const CompositeRequest& req, ImageRgba8& out) override;
  /// Draws the overlay into the picture last drawn (GL_LINES for overlay_geometry()'s segments,
  /// the HUD strip as a textured quad, alpha-blended, its texture re-uploaded only when the
  /// strip's revision changes) and, if that draw read back, reads the viewport back into `out`.
  /// Nothing is drawn before the first draw() of `out`'s size.
  void draw_overlay(const Overlay& overlay, const Viewport& vp, ImageRgba8& out) override;
  /// Blits the last picture to the window and swaps buffers.
  void present() override;
  const CompositorStats& stats() const override { return stats_; }

  /// HUD strip texture uploads so far (one per text change of the strip drawn).
  uint64_t hud_uploads() const { return hud_uploads_; }
  std::string renderer() const;  ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version() const;   ///< GL_VERSION
  gl::Window& window() { return *window_; }

 private:
  struct GpuMesh {
    gl::VertexArray vao;
    gl::Buffer vertices;
    gl::Buffer indices;
    gl::Texture texture;
    int index_count = 0;
  };
  struct UploadKey {
    const void* frame = nullptr;
    uint64_t sequence = 0;
    int64_t host_timestamp_ns = 0;
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool operator==(const UploadKey&) const = default;
  };

  void ensure_targets(int width, int height);
  void upload_scene(const SyntheticScene& scene);
  void upload_video(const CompositeRequest& req);

  std::unique_ptr<gl::Window> window_;  // first member: the context outlives every GL object
  CompositorStats stats_;

  gl::Program mesh_program_;
  gl::Program composite_program_;
  gl::VertexArray empty_vao_;  // the full-screen pass makes its triangle from gl_VertexID

  int target_w_ = 0, target_h_ = 0;
  gl::Texture synth_colour_;
  gl::Renderbuffer synth_depth_;
  gl::Framebuffer synth_fbo_;
  gl::Texture final_colour_;
  gl::Framebuffer final_fbo_;

  std::vector<GpuMesh> meshes_;
  const SyntheticScene* scene_ = nullptr;
  uint64_t scene_revision_ = 0;
  bool scene_loaded_ = false;

  gl::Texture video_texture_;
  int video_w_ = 0, video_h_ = 0;
  UploadKey last_upload_;
  bool have_upload_ = false;

  // Overlay: a preallocated vertex buffer for the segments (x, y, r, g, b per vertex) and the
  // HUD strip's texture.
  gl::Program lines_program_;
  gl::Program hud_program_;
  gl::VertexArray lines_vao_;
  gl::Buffer lines_vbo_;
  std::array<float, OverlaySegments::kCapacity * 2 * 5> line_vertices_{};
  gl::Texture hud_texture_;
  const HudStrip* hud_uploaded_ = nullptr;
  uint64_t hud_revision_ = 0;
  int hud_w_ = 0, hud_h_ = 0;
  uint64_t hud_uploads_ = 0;
  bool last_read_back_ = false;
  int u_lines_target_ = -1;
  int u_hud_origin_ = -1, u_hud_size_ = -1, u_hud_target_ = -1;

  // Uniform locations (looked up once).
  int u_world_to_clip_ = -1;
  struct CompositeUniforms {
    int synth, video, vp_origin, vp_size, video_on, H, inv_depth, inv_near, video_size;
    int per_pixel, w_video, nearest, style, desat, checker_step, cell, frame_w, frame_rgb, fade,
        stale;
  } cu_{};
};

}  // namespace hd::render
