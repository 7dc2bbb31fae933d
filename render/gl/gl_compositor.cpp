#include "render/gl/gl_compositor.h"

#include <epoxy/gl.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/compositor/depth_warp.h"
#include "render/compositor/request_check.h"
#include "render/compositor/video_warp.h"
#include "render/gl/gl_program.h"
#include "render/gl/gl_projection.h"
#include "render/gl/shader_sources.h"  // generated from render/gl/shaders/

namespace hd::render {

namespace {

void set_sampling(GLenum target) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_BASE_LEVEL, 0);
  glTexParameteri(target, GL_TEXTURE_MAX_LEVEL, 0);
}

const SyntheticScene& empty_scene() {
  static const SyntheticScene scene;
  return scene;
}

}  // namespace

GlCompositor::GlCompositor(const gl::WindowOptions& options)
    : window_(std::make_unique<gl::Window>(options)) {
  GLint major = 0, minor = 0, profile = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
  if (major * 10 + minor < 33 || !(profile & GL_CONTEXT_CORE_PROFILE_BIT)) {
    throw std::runtime_error("GL compositor: got OpenGL " + std::to_string(major) + "." +
                             std::to_string(minor) + ", need a 3.3 core context");
  }
  mesh_program_ = gl::link_program(shaders::kMeshVert, shaders::kMeshFrag, "mesh");
  composite_program_ =
      gl::link_program(shaders::kFullScreenVert, shaders::kCompositeFrag, "composite");
  empty_vao_ = gl::VertexArray::create();
  u_world_to_clip_ = glGetUniformLocation(mesh_program_.get(), "world_to_clip");
  glUseProgram(mesh_program_.get());
  glUniform1i(glGetUniformLocation(mesh_program_.get(), "tex"), 0);
  const GLuint c = composite_program_.get();
  auto loc = [c](const char* n) { return glGetUniformLocation(c, n); };
  cu_ = {loc("synth"),     loc("video"),    loc("vp_origin"),
         loc("vp_size"),   loc("video_on"), loc("H"),
         loc("inv_depth"), loc("inv_near"), loc("video_size"),
         loc("per_pixel"), loc("w_video"),  loc("nearest"),
         loc("style"),     loc("desat"),    loc("checker_step"),
         loc("cell"),      loc("frame_w"),  loc("frame_rgb"),
         loc("fade"),      loc("stale"),    loc("model_depth"),
         loc("A"),         loc("b"),        loc("seen_tolerance")};
  glUseProgram(c);
  glUniform1i(cu_.synth, 0);
  glUniform1i(cu_.video, 1);
  glUniform1i(loc("eye_depth"), 2);
  glUniform1i(loc("seen"), 3);
  glUniform1f(cu_.seen_tolerance, kSeenTolerance);
  glUseProgram(0);
  video_texture_ = gl::Texture::create();
  glBindTexture(GL_TEXTURE_2D, video_texture_.get());
  set_sampling(GL_TEXTURE_2D);

  lines_program_ = gl::link_program(shaders::kLinesVert, shaders::kLinesFrag, "overlay lines");
  hud_program_ = gl::link_program(shaders::kHudVert, shaders::kHudFrag, "overlay hud");
  u_lines_target_ = glGetUniformLocation(lines_program_.get(), "target");
  u_hud_origin_ = glGetUniformLocation(hud_program_.get(), "origin");
  u_hud_size_ = glGetUniformLocation(hud_program_.get(), "size");
  u_hud_target_ = glGetUniformLocation(hud_program_.get(), "target");
  glUseProgram(hud_program_.get());
  glUniform1i(glGetUniformLocation(hud_program_.get(), "strip"), 0);
  glUseProgram(0);
  lines_vao_ = gl::VertexArray::create();
  lines_vbo_ = gl::Buffer::create();
  glBindVertexArray(lines_vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, lines_vbo_.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(sizeof line_vertices_), nullptr,
               GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(float),
                        reinterpret_cast<const void*>(2 * sizeof(float)));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  hud_texture_ = gl::Texture::create();
  glBindTexture(GL_TEXTURE_2D, hud_texture_.get());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glDisable(GL_FRAMEBUFFER_SRGB);
  glDisable(GL_DITHER);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
}

GlCompositor::~GlCompositor() {
  // GL objects must die while the context is current; members after window_ do so first.
  window_->make_current();
}

std::string GlCompositor::renderer() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return s ? s : "";
}

std::string GlCompositor::version() const {
  const auto* s = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return s ? s : "";
}

void GlCompositor::ensure_targets(int width, int height) {
  if (width == target_w_ && height == target_h_) return;
  target_w_ = width;
  target_h_ = height;
  synth_colour_ = gl::Texture::create();
  glBindTexture(GL_TEXTURE_2D, synth_colour_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  synth_inv_depth_ = gl::Texture::create();
  glBindTexture(GL_TEXTURE_2D, synth_inv_depth_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width, height, 0, GL_RED, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  synth_depth_ = gl::Renderbuffer::create();
  glBindRenderbuffer(GL_RENDERBUFFER, synth_depth_.get());
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  synth_fbo_ = gl::Framebuffer::create();
  glBindFramebuffer(GL_FRAMEBUFFER, synth_fbo_.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, synth_colour_.get(),
                         0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D,
                         synth_inv_depth_.get(), 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                            synth_depth_.get());
  const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, both);
  final_colour_ = gl::Texture::create();
  glBindTexture(GL_TEXTURE_2D, final_colour_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  final_fbo_ = gl::Framebuffer::create();
  glBindFramebuffer(GL_FRAMEBUFFER, final_fbo_.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, final_colour_.get(),
                         0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void GlCompositor::upload_scene(const SyntheticScene& scene) {
  if (scene_loaded_ && scene_ == &scene && scene_revision_ == scene.revision) return;
  meshes_.clear();
  meshes_.reserve(scene.meshes.size());
  std::vector<float> interleaved;
  for (const TexturedMesh& mesh : scene.meshes) {
    if (!mesh.valid() || mesh.triangles.empty()) continue;  // the CPU reference skips it too
    GpuMesh g;
    interleaved.clear();
    for (std::size_t i = 0; i < mesh.positions_m.size(); ++i) {
      const auto& p = mesh.positions_m[i];
      const auto& uv = mesh.uvs[i];
      interleaved.insert(interleaved.end(), {p.x(), p.y(), p.z(), uv.x(), uv.y()});
    }
    g.vao = gl::VertexArray::create();
    glBindVertexArray(g.vao.get());
    g.vertices = gl::Buffer::create();
    glBindBuffer(GL_ARRAY_BUFFER, g.vertices.get());
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
                 interleaved.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 5 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 5 * sizeof(float),
                          reinterpret_cast<const void*>(3 * sizeof(float)));
    g.indices = gl::Buffer::create();
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.indices.get());
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh.triangles.size() * sizeof(mesh.triangles[0])),
                 mesh.triangles.data(), GL_STATIC_DRAW);
    g.index_count = static_cast<int>(mesh.triangles.size() * 3);
    glBindVertexArray(0);
    g.texture = gl::Texture::create();
    glBindTexture(GL_TEXTURE_2D, g.texture.get());
    set_sampling(GL_TEXTURE_2D);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, mesh.texture.stride_bytes / 4);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, mesh.texture.width, mesh.texture.height, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, mesh.texture.data.data());
    meshes_.push_back(std::move(g));
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  scene_ = &scene;
  scene_revision_ = scene.revision;
  scene_loaded_ = true;
  ++stats_.scene_uploads;
}

void GlCompositor::upload_video(const CompositeRequest& req) {
  const drivers::Frame& f = *req.video;
  glBindTexture(GL_TEXTURE_2D, video_texture_.get());
  if (f.width != video_w_ || f.height != video_h_) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, f.width, f.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 nullptr);
    video_w_ = f.width;
    video_h_ = f.height;
    have_upload_ = false;
  }
  // The region grown to whole pixels plus the one-pixel bilinear neighbourhood, inside the frame.
  const core::PixelRect& g = req.region;
  auto lo = [](double x, int n) {
    return static_cast<int>(std::clamp(std::floor(x) - 1.0, 0.0, static_cast<double>(n)));
  };
  auto hi = [](double x, int n) {
    return static_cast<int>(std::clamp(std::ceil(x) + 1.0, 0.0, static_cast<double>(n)));
  };
  const UploadKey key{&f,
                      f.sequence,
                      f.host_timestamp_ns,
                      lo(g.u_min, f.width),
                      lo(g.v_min, f.height),
                      hi(g.u_max, f.width),
                      hi(g.v_max, f.height)};
  if (have_upload_ && key == last_upload_) return;
  const int w = key.x1 - key.x0, h = key.y1 - key.y0;
  if (w > 0 && h > 0) {
    glPixelStorei(GL_UNPACK_ROW_LENGTH, f.stride_bytes / 4);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, key.x0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, key.y0);
    glTexSubImage2D(GL_TEXTURE_2D, 0, key.x0, key.y0, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
                    f.data.data());
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    stats_.video_bytes_uploaded += static_cast<uint64_t>(w) * static_cast<uint64_t>(h) * 4u;
    ++stats_.video_uploads;
  }
  last_upload_ = key;
  have_upload_ = true;
}

void GlCompositor::draw_meshes(const Eigen::Matrix4f& world_to_clip) {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glUseProgram(mesh_program_.get());
  glUniformMatrix4fv(u_world_to_clip_, 1, GL_FALSE, world_to_clip.data());
  glActiveTexture(GL_TEXTURE0);
  for (const GpuMesh& g : meshes_) {
    glBindTexture(GL_TEXTURE_2D, g.texture.get());
    glBindVertexArray(g.vao.get());
    glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
}

void GlCompositor::draw(const CompositeRequest& req, ImageRgba8& out) {
  if (!request_drawable(req, out)) {
    ++stats_.requests_rejected;
    return;
  }
  window_->make_current();
  ensure_targets(out.width, out.height);
  const SyntheticScene& scene = req.scene ? *req.scene : empty_scene();
  upload_scene(scene);

  bool video_on = false;
  VideoWarp warp;
  if (req.video != nullptr && req.has_region) {
    if (video_usable(req)) {
      warp = VideoWarp::make(req.eye, req.T_world_eye, req.real, req.T_world_real, req.d_m);
      video_on = warp.usable;
      if (video_on) upload_video(req);
    } else {
      ++stats_.video_frames_rejected;
    }
  }
  DepthWarp depth_warp;
  if (video_on && req.video_view == core::VideoView::kModelDepth) {
    depth_warp = DepthWarp::make(req.eye, req.T_world_eye, req.real, req.T_world_real);
    if (depth_warp.usable) draw_camera_depth(req, scene);
  }

  const Viewport& vp = req.viewport;
  // Pass 1: the model, depth-tested, into the synthetic colour target.
  glBindFramebuffer(GL_FRAMEBUFFER, synth_fbo_.get());
  glViewport(vp.x, vp.y, vp.width, vp.height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(vp.x, vp.y, vp.width, vp.height);
  const GLfloat background[4] = {scene.background_rgb[0] / 255.0f, scene.background_rgb[1] / 255.0f,
                                 scene.background_rgb[2] / 255.0f, 1.0f};
  const GLfloat no_surface[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const GLfloat far_depth = 1.0f;
  glClearBufferfv(GL_COLOR, 0, background);
  glClearBufferfv(GL_COLOR, 1, no_surface);
  glClearBufferfv(GL_DEPTH, 0, &far_depth);
  if (!meshes_.empty())
    draw_meshes(gl::world_to_clip(req.eye, req.T_world_eye, req.near_m, req.far_m));

  // Pass 2: video, blend and marks, into the final target.
  glBindFramebuffer(GL_FRAMEBUFFER, final_fbo_.get());
  glUseProgram(composite_program_.get());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, synth_colour_.get());
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, video_texture_.get());
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, synth_inv_depth_.get());
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, camera_depth_.get());
  glActiveTexture(GL_TEXTURE0);
  const core::MarkingParams mark = req.marking.sanitized();
  const double w_video =
      std::isnan(req.transition.w_video) ? 0.0 : std::clamp(req.transition.w_video, 0.0, 1.0);
  glUniform2i(cu_.vp_origin, vp.x, vp.y);
  glUniform2i(cu_.vp_size, vp.width, vp.height);
  glUniform1i(cu_.video_on, video_on ? 1 : 0);
  if (video_on) {
    const Eigen::Matrix3f Hf = warp.H.cast<float>();
    glUniformMatrix3fv(cu_.H, 1, GL_FALSE, Hf.data());
    glUniform3f(cu_.inv_depth, static_cast<float>(warp.inv_depth.x()),
                static_cast<float>(warp.inv_depth.y()), static_cast<float>(warp.inv_depth.z()));
    glUniform1f(cu_.inv_near, static_cast<float>(1.0 / req.near_m));
    glUniform2f(cu_.video_size, static_cast<float>(video_w_), static_cast<float>(video_h_));
  }
  glUniform1i(cu_.model_depth, depth_warp.usable ? 1 : 0);
  if (depth_warp.usable) {
    const Eigen::Matrix3f Af = depth_warp.A.cast<float>();
    glUniformMatrix3fv(cu_.A, 1, GL_FALSE, Af.data());
    glUniform3f(cu_.b, static_cast<float>(depth_warp.b.x()), static_cast<float>(depth_warp.b.y()),
                static_cast<float>(depth_warp.b.z()));
  }
  glUniform1i(cu_.per_pixel, req.mode == core::TransitionMode::kPerPixel ? 1 : 0);
  glUniform1f(cu_.w_video, static_cast<float>(w_video));
  glUniform1i(cu_.nearest, req.sampling == VideoSampling::kNearest ? 1 : 0);
  int style = 0;
  switch (mark.style) {
    case core::MarkingStyle::kNone:
      style = 0;
      break;
    case core::MarkingStyle::kFrame:
      style = 1;
      break;
    case core::MarkingStyle::kDesaturate:
      style = 2;
      break;
    case core::MarkingStyle::kChecker:
      style = 3;
      break;
  }
  glUniform1i(cu_.style, style);
  glUniform1f(cu_.desat, static_cast<float>(mark.synthetic_desaturation));
  glUniform1f(cu_.checker_step, static_cast<float>(0.5 * mark.checker_contrast * 255.0));
  glUniform1i(cu_.cell, mark.checker_cell_px);
  glUniform1i(cu_.frame_w, mark.frame_width_px);
  glUniform1f(cu_.fade, static_cast<float>(mark.synthetic_fade));
  glUniform1i(cu_.stale, mark.video_stale ? 1 : 0);
  const core::Rgb& fc =
      mark.video_stale ? mark.stale_rgb : mark.frame_colour(req.transition.variant);
  glUniform3f(cu_.frame_rgb, fc.r, fc.g, fc.b);
  glBindVertexArray(empty_vao_.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glDisable(GL_SCISSOR_TEST);

  last_read_back_ = req.read_back;
  if (req.read_back) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, final_fbo_.get());
    glPixelStorei(GL_PACK_ROW_LENGTH, out.stride_bytes / 4);
    glReadPixels(vp.x, vp.y, vp.width, vp.height, GL_RGBA, GL_UNSIGNED_BYTE, out.pixel(vp.x, vp.y));
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  ++stats_.frames_drawn;
}

void GlCompositor::load_picture(const ImageRgba8& picture) {
  window_->make_current();
  ensure_targets(picture.width, picture.height);
  glBindTexture(GL_TEXTURE_2D, final_colour_.get());
  glPixelStorei(GL_UNPACK_ROW_LENGTH, picture.stride_bytes / 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, picture.width, picture.height, GL_RGBA, GL_UNSIGNED_BYTE,
                  picture.data.data());
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  last_read_back_ = true;
}

void GlCompositor::present() {
  window_->make_current();
  int fb_w = 0, fb_h = 0;
  window_->framebuffer_size(&fb_w, &fb_h);
  const bool panel = lens_ != nullptr && lens_index_count_ > 0;
  const int w = panel ? panel_w_ : target_w_, h = panel ? panel_h_ : target_h_;
  if (target_w_ > 0 && fb_w > 0 && fb_h > 0) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, panel ? panel_fbo_.get() : final_fbo_.get());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    // Picture row 0 is framebuffer row 0; the window's row 0 is at the bottom: flip on blit.
    glBlitFramebuffer(0, 0, w, h, 0, fb_h, fb_w, 0, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  window_->swap_buffers();
}

}  // namespace hd::render
