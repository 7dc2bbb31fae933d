// GlCompositor's lens pass: the distortion mesh or exact fragment pass built by set_lens, and
// predistort() drawing the composited eyes through it into the panel target (the rest of the
// class: gl_compositor.cpp).
#include "render/gl/gl_compositor.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <vector>

#include "render/gl/gl_program.h"
#include "render/gl/shader_sources.h"  // generated from render/gl/shaders/
#include "render/lens/lens_warp.h"

namespace hd::render {

void GlCompositor::set_lens(const lens::LensWarp* warp) {
  window_->make_current();
  lens_ = warp;
  lens_index_count_ = 0;
  if (!warp) return;
  if (!lens_program_) {
    lens_program_ = gl::link_program(shaders::kLensVert, shaders::kLensFrag, "lens");
    glUseProgram(lens_program_.get());
    glUniform1i(glGetUniformLocation(lens_program_.get(), "eyes"), 0);
    glUseProgram(0);
  }
  // Exact per fragment: two triangles per eye carry the eye index only.
  const int step = lens_mesh_step_px_ > 0 ? lens_mesh_step_px_ : 1 << 20;
  const int hw = warp->eye_panel_width(), h = warp->panel_height();
  std::vector<int> xs, ys;
  for (int x = 0; x < hw; x += step) xs.push_back(x);
  xs.push_back(hw);
  for (int y = 0; y < h; y += step) ys.push_back(y);
  ys.push_back(h);
  std::vector<float> vertices;
  std::vector<GLuint> indices;
  for (int e = 0; e < 2; ++e) {
    const GLuint first = static_cast<GLuint>(vertices.size() / 5);
    for (int y : ys)
      for (int x : xs) {
        double u = 0, v = 0;
        warp->source_unclamped(e, x, y, 1, &u, &v);
        for (double value :
             {double(x + e * hw), double(y), u + e * warp->eye_width(), v, double(e)})
          vertices.push_back(static_cast<float>(value));
      }
    const GLuint nx = static_cast<GLuint>(xs.size());
    for (GLuint j = 0; j + 1 < ys.size(); ++j)
      for (GLuint i = 0; i + 1 < nx; ++i) {
        const GLuint a = first + j * nx + i, b = a + 1, c = a + nx, d = c + 1;
        for (GLuint k : {a, b, c, b, d, c}) indices.push_back(k);
      }
  }
  lens_vao_ = gl::VertexArray::create();
  lens_vbo_ = gl::Buffer::create();
  lens_ibo_ = gl::Buffer::create();
  glBindVertexArray(lens_vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, lens_vbo_.get());
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
               vertices.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, lens_ibo_.get());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)),
               indices.data(), GL_STATIC_DRAW);
  const GLsizei stride = 5 * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(2 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride,
                        reinterpret_cast<const void*>(4 * sizeof(float)));
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  lens_index_count_ = static_cast<int>(indices.size());

  panel_w_ = warp->panel_width();
  panel_h_ = warp->panel_height();
  panel_colour_ = gl::Texture::create();
  glBindTexture(GL_TEXTURE_2D, panel_colour_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, panel_w_, panel_h_, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
  panel_fbo_ = gl::Framebuffer::create();
  glBindFramebuffer(GL_FRAMEBUFFER, panel_fbo_.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, panel_colour_.get(),
                         0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  // Uniforms fixed by the profile.
  const lens::HmdProfile& prof = warp->profile();
  const GLuint l = lens_program_.get();
  glUseProgram(l);
  glUniform2f(glGetUniformLocation(l, "panel_size"), static_cast<float>(panel_w_),
              static_cast<float>(panel_h_));
  glUniform2f(glGetUniformLocation(l, "eyes_size"), static_cast<float>(2 * warp->eye_width()),
              static_cast<float>(warp->eye_height()));
  const float centre[4] = {static_cast<float>(warp->eye(0).cx), static_cast<float>(warp->eye(0).cy),
                           static_cast<float>(warp->eye(1).cx + warp->eye_width()),
                           static_cast<float>(warp->eye(1).cy)};
  glUniform2fv(glGetUniformLocation(l, "centre"), 2, centre);
  float lens_px[4];
  for (int e = 0; e < 2; ++e) {
    lens_px[2 * e] = static_cast<float>(prof.lens_centre_m[e].x() / prof.pitch_x_m() + e * hw);
    lens_px[2 * e + 1] = static_cast<float>(prof.lens_centre_m[e].y() / prof.pitch_y_m());
  }
  glUniform2fv(glGetUniformLocation(l, "lens_px"), 2, lens_px);
  glUniform2f(glGetUniformLocation(l, "inv_unit_px"),
              static_cast<float>(prof.pitch_x_m() / prof.r_unit_m.x()),
              static_cast<float>(prof.pitch_y_m() / prof.r_unit_m.y()));
  glUniform1f(glGetUniformLocation(l, "max_radius"), static_cast<float>(prof.max_radius));
  glUniform3f(glGetUniformLocation(l, "scale"), static_cast<float>(warp->channel_scale(0)), 1.0f,
              static_cast<float>(warp->channel_scale(2)));
  glUniform1f(glGetUniformLocation(l, "eye_w"), static_cast<float>(warp->eye_width()));
  glUniform1i(glGetUniformLocation(l, "exact"), lens_mesh_step_px_ == 0 ? 1 : 0);
  float k[12] = {};
  const std::size_t nk = std::min<std::size_t>(12, prof.coefficients.size());
  for (std::size_t i = 0; i < nk; ++i) k[i] = static_cast<float>(prof.coefficients[i]);
  glUniform1fv(glGetUniformLocation(l, "k"), 12, k);
  glUniform1i(glGetUniformLocation(l, "k_count"), static_cast<int>(nk));
  glUseProgram(0);
}

void GlCompositor::predistort(const ImageRgba8& eyes, ImageRgba8& panel) {
  if (!lens_ || lens_index_count_ == 0) return;
  if (target_w_ < 2 * lens_->eye_width() || target_h_ < lens_->eye_height() ||
      eyes.width != target_w_ ||
      (last_read_back_ && (panel.width != panel_w_ || panel.height != panel_h_))) {
    ++stats_.requests_rejected;
    return;
  }
  window_->make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, panel_fbo_.get());
  glViewport(0, 0, panel_w_, panel_h_);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glUseProgram(lens_program_.get());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, final_colour_.get());
  // The composited eyes are sampled bilinearly here (the compositing passes only fetch texels).
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindVertexArray(lens_vao_.get());
  glDrawElements(GL_TRIANGLES, lens_index_count_, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  glUseProgram(0);
  if (last_read_back_) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, panel_fbo_.get());
    glPixelStorei(GL_PACK_ROW_LENGTH, panel.stride_bytes / 4);
    glReadPixels(0, 0, panel_w_, panel_h_, GL_RGBA, GL_UNSIGNED_BYTE, panel.data.data());
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace hd::render
