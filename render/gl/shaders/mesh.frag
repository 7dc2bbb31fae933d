// The model's texture, opaque, and its inverse depth 1 / z_eye (the model-depth video view's
// input; gl_FragCoord.w is 1 / w_clip and w_clip = z_eye).
#version 330 core
uniform sampler2D tex;
in vec2 v_uv;
layout(location = 0) out vec4 colour;
layout(location = 1) out float inv_depth;
void main() {
  colour = vec4(texture(tex, v_uv).rgb, 1.0);
  inv_depth = gl_FragCoord.w;
}
