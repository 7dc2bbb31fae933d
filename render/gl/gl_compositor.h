#pragma once
// The OpenGL 3.3 core compositor: the CPU reference's picture, drawn by shaders. Defined in
// gl_compositor.cpp (targets, uploads, the compositing passes, present), gl_compositor_overlay.cpp
// (the overlay pass), gl_compositor_lens.cpp (the lens pass) and gl_compositor_depth.cpp (the
// model seen from the real camera, for the model-depth view); programs via gl_program.h.

#include <Eigen/Core>
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
/// synthetic colour and paints the marks. The mesh pass also keeps the model's 1 / z_eye in a
/// second target; the model-depth view reads it, and a depth map of the model drawn from the
/// real camera (only when model or camera changed), in the same full-screen pass. Framebuffer row r
/// is picture row r (y down), so a read-back needs no flip; present() blits it upright to the
/// window.
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
  /// The lens pass over each eye's half of the panel. By default (mesh step 0) a fragment pass:
  /// each fragment evaluates the lens polynomial for its green sample point; with a mesh step N
  /// a distortion mesh instead, one vertex every N panel px holding the green point
  /// (lens::LensWarp::source), linearly interpolated (cheaper per fragment, but it leaves a
  /// geometric error: bench/lens). Either way the shader scales the green point to R and B about
  /// the eye's principal point (affine, so exact under interpolation too), samples the drawn
  /// eyes GL_LINEAR clamped to the pixel's own eye, and blacks out beyond the usable radius,
  /// computed per fragment. The panel target is panel-sized; present() shows it.
  void set_lens(const lens::LensWarp* warp) override;
  void predistort(const ImageRgba8& eyes, ImageRgba8& panel) override;
  /// 0 (default): the exact fragment pass; N > 0: a distortion mesh with a vertex every N px.
  /// Takes effect at the next set_lens.
  void set_lens_mesh_step(int step_px) { lens_mesh_step_px_ = step_px < 0 ? 0 : step_px; }
  /// Replaces the drawn picture by `picture` (passes after compositing, tested on their own).
  void load_picture(const ImageRgba8& picture);
  /// Blits the last picture (the panel's, with a lens) to the window and swaps buffers.
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
  /// Every mesh, depth-tested, with the mesh program into the bound framebuffer.
  void draw_meshes(const Eigen::Matrix4f& world_to_clip);

  std::unique_ptr<gl::Window> window_;  // first member: the context outlives every GL object
  CompositorStats stats_;

  gl::Program mesh_program_;
  gl::Program composite_program_;
  gl::VertexArray empty_vao_;  // the full-screen pass makes its triangle from gl_VertexID

  int target_w_ = 0, target_h_ = 0;
  gl::Texture synth_colour_;
  gl::Texture synth_inv_depth_;  ///< R32F, the model's 1 / z_eye (0: no surface)
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

  // The lens pass (set_lens).
  const lens::LensWarp* lens_ = nullptr;
  int lens_mesh_step_px_ = 0;
  gl::Program lens_program_;
  gl::VertexArray lens_vao_;
  gl::Buffer lens_vbo_;
  gl::Buffer lens_ibo_;
  int lens_index_count_ = 0;
  gl::Texture panel_colour_;
  gl::Framebuffer panel_fbo_;
  int panel_w_ = 0, panel_h_ = 0;
  int u_lines_target_ = -1;
  int u_hud_origin_ = -1, u_hud_size_ = -1, u_hud_target_ = -1;

  // Uniform locations (looked up once).
  int u_world_to_clip_ = -1;
  struct CompositeUniforms {
    int synth, video, vp_origin, vp_size, video_on, H, inv_depth, inv_near, video_size;
    int per_pixel, w_video, nearest, style, desat, checker_step, cell, frame_w, frame_rgb, fade,
        stale, model_depth, A, b, seen_tolerance;
  } cu_{};

  // The model-depth view's depth map of the model seen from the real camera
  // (gl_compositor_depth.cpp): re-drawn only when the key changes.
  struct CameraDepthKey {
    const void* scene = nullptr;
    uint64_t revision = 0;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    int width = 0, height = 0;
    std::array<double, 12> pose{};
    double near_m = 0, far_m = 0;
    bool operator==(const CameraDepthKey&) const = default;
  };
  void draw_camera_depth(const CompositeRequest& req, const SyntheticScene& scene);
  gl::Texture camera_depth_;  ///< R32F, 1 / z_real (0: no surface), the real frame's size
  gl::Renderbuffer camera_depth_z_;
  gl::Framebuffer camera_depth_fbo_;
  int camera_depth_w_ = 0, camera_depth_h_ = 0;
  CameraDepthKey camera_depth_key_;
  bool have_camera_depth_ = false;
};

}  // namespace hd::render
