// The model's textured mesh: workspace positions (m) to clip space.
#version 330 core
layout(location = 0) in vec3 pos_m;
layout(location = 1) in vec2 uv;
uniform mat4 world_to_clip;
out vec2 v_uv;
void main() {
  v_uv = uv;
  gl_Position = world_to_clip * vec4(pos_m, 1.0);
}
