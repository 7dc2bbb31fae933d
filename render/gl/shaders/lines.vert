// Overlay lines: vertices in output pixels (row 0 at the top, like framebuffer row 0).
#version 330 core
layout(location = 0) in vec2 pos_px;
layout(location = 1) in vec3 rgb;
uniform vec2 target;
flat out vec3 v_rgb;
void main() {
  v_rgb = rgb;
  gl_Position = vec4(pos_px / target * 2.0 - 1.0, 0.0, 1.0);
}
