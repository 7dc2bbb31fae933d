// The GL compositor's depth map of the model seen from the real camera: the model-depth video
// view's visibility test (gl_compositor.h; the CPU reference's CameraDepthMap).
#include <epoxy/gl.h>

#include "render/gl/gl_compositor.h"
#include "render/gl/gl_projection.h"

namespace hd::render {

void GlCompositor::draw_camera_depth(const CompositeRequest& req, const SyntheticScene& scene) {
  const core::Pinhole& c = req.real;
  CameraDepthKey key{&scene,  scene.revision, c.fx, c.fy,       c.cx,     c.cy,
                     c.width, c.height,       {},   req.near_m, req.far_m};
  for (int i = 0; i < 9; ++i)
    key.pose[static_cast<std::size_t>(i)] = req.T_world_real.R(i % 3, i / 3);
  for (int i = 0; i < 3; ++i) key.pose[static_cast<std::size_t>(9 + i)] = req.T_world_real.t(i);
  if (have_camera_depth_ && key == camera_depth_key_) return;
  if (c.width != camera_depth_w_ || c.height != camera_depth_h_) {
    camera_depth_ = gl::Texture::create();
    glBindTexture(GL_TEXTURE_2D, camera_depth_.get());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, c.width, c.height, 0, GL_RED, GL_FLOAT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    camera_depth_z_ = gl::Renderbuffer::create();
    glBindRenderbuffer(GL_RENDERBUFFER, camera_depth_z_.get());
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, c.width, c.height);
    camera_depth_fbo_ = gl::Framebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, camera_depth_fbo_.get());
    // The mesh program writes 1 / z to its second output; its colour goes nowhere.
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, camera_depth_.get(),
                           0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                              camera_depth_z_.get());
    const GLenum second_only[2] = {GL_NONE, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, second_only);
    camera_depth_w_ = c.width;
    camera_depth_h_ = c.height;
  }
  glBindFramebuffer(GL_FRAMEBUFFER, camera_depth_fbo_.get());
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, c.width, c.height);
  const GLfloat no_surface[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const GLfloat far_depth = 1.0f;
  glClearBufferfv(GL_COLOR, 1, no_surface);
  glClearBufferfv(GL_DEPTH, 0, &far_depth);
  draw_meshes(gl::world_to_clip(c, req.T_world_real, req.near_m, req.far_m));
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  camera_depth_key_ = key;
  have_camera_depth_ = true;
  ++stats_.camera_depth_renders;
}

}  // namespace hd::render
