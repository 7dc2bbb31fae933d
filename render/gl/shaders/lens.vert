// The lens pass: vertices at panel positions (px) carrying the green sample point (eyes-picture
// px) and the eye; see GlCompositor::set_lens.
#version 330 core
layout(location = 0) in vec2 panel_px;
layout(location = 1) in vec2 green_px;
layout(location = 2) in float eye;
uniform vec2 panel_size;
out vec2 green;
flat out int eye_i;
void main() {
  green = green_px;
  eye_i = int(eye + 0.5);
  gl_Position = vec4(panel_px / panel_size * 2.0 - 1.0, 0.0, 1.0);
}
