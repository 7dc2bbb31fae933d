// Overlay lines: one flat colour per line.
#version 330 core
flat in vec3 v_rgb;
out vec4 colour;
void main() { colour = vec4(v_rgb, 1.0); }
