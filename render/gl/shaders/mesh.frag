// The model's texture, opaque.
#version 330 core
uniform sampler2D tex;
in vec2 v_uv;
out vec4 colour;
void main() { colour = vec4(texture(tex, v_uv).rgb, 1.0); }
