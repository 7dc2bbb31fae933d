// GlCompositor's overlay pass: the overlay's segments as GL_LINES and the HUD strip as a textured
// quad, drawn over the composited picture (the rest of the class: gl_compositor.cpp).
#include "render/gl/gl_compositor.h"

#include <epoxy/gl.h>

#include <Eigen/Core>
#include <algorithm>

namespace hd::render {

void GlCompositor::draw_overlay(const Overlay& overlay, const Viewport& vp, ImageRgba8& out) {
  if (overlay.empty() || target_w_ <= 0 || out.width != target_w_ || out.height != target_h_ ||
      vp.width <= 0 || vp.height <= 0 || vp.x < 0 || vp.y < 0 || vp.x + vp.width > out.width ||
      vp.y + vp.height > out.height)
    return;
  window_->make_current();
  OverlaySegments segs;
  overlay_geometry(overlay, vp, segs);
  glBindFramebuffer(GL_FRAMEBUFFER, final_fbo_.get());
  glViewport(0, 0, target_w_, target_h_);
  glEnable(GL_SCISSOR_TEST);
  glScissor(vp.x, vp.y, vp.width, vp.height);
  const float tw = static_cast<float>(target_w_), th = static_cast<float>(target_h_);
  if (segs.count > 0) {
    std::size_t k = 0;
    for (int i = 0; i < segs.count; ++i) {
      const OverlaySegment& s = segs.segment[static_cast<std::size_t>(i)];
      for (const Eigen::Vector2d& p : {s.a, s.b}) {
        line_vertices_[k++] = static_cast<float>(p.x());
        line_vertices_[k++] = static_cast<float>(p.y());
        for (int c = 0; c < 3; ++c)
          line_vertices_[k++] = s.rgb[static_cast<std::size_t>(c)] / 255.0f;
      }
    }
    glBindBuffer(GL_ARRAY_BUFFER, lines_vbo_.get());
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(k * sizeof(float)),
                    line_vertices_.data());
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glUseProgram(lines_program_.get());
    glUniform2f(u_lines_target_, tw, th);
    glBindVertexArray(lines_vao_.get());
    glDrawArrays(GL_LINES, 0, 2 * segs.count);
  }
  if (overlay.draws_hud()) {
    const ImageRgba8& strip = overlay.hud->image();
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, hud_texture_.get());
    // The texture holds the strip's every line, so a change of line count re-uploads only.
    const int cap_h = overlay.hud->capacity_height();
    if (hud_uploaded_ != overlay.hud || hud_revision_ != overlay.hud->revision() ||
        hud_w_ != strip.width || hud_h_ != cap_h) {
      glPixelStorei(GL_UNPACK_ROW_LENGTH, strip.stride_bytes / 4);
      if (hud_w_ != strip.width || hud_h_ != cap_h) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, strip.width, cap_h, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     nullptr);
        hud_w_ = strip.width;
        hud_h_ = cap_h;
      }
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, strip.width, strip.height, GL_RGBA, GL_UNSIGNED_BYTE,
                      strip.data.data());
      glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
      hud_uploaded_ = overlay.hud;
      hud_revision_ = overlay.hud->revision();
      ++hud_uploads_;
    }
    glEnable(GL_BLEND);
    // Colour: strip over picture by the strip's alpha; the picture's alpha stays.
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glUseProgram(hud_program_.get());
    glUniform2f(u_hud_origin_, static_cast<float>(vp.x), static_cast<float>(vp.y));
    glUniform2f(u_hud_size_, static_cast<float>(std::min(strip.width, vp.width)),
                static_cast<float>(std::min(strip.height, vp.height)));
    glUniform2f(u_hud_target_, tw, th);
    glBindVertexArray(empty_vao_.get());
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glDisable(GL_BLEND);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  glDisable(GL_SCISSOR_TEST);
  if (last_read_back_) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, final_fbo_.get());
    glPixelStorei(GL_PACK_ROW_LENGTH, out.stride_bytes / 4);
    glReadPixels(vp.x, vp.y, vp.width, vp.height, GL_RGBA, GL_UNSIGNED_BYTE, out.pixel(vp.x, vp.y));
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace hd::render
