// The HUD strip: a quad at `origin` of `size` pixels, texel (x, y) of the strip on pixel
// origin + (x, y), blended by the strip's alpha.
#version 330 core
uniform vec2 origin;
uniform vec2 size;
uniform vec2 target;
void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
  gl_Position = vec4((origin + corner * size) / target * 2.0 - 1.0, 0.0, 1.0);
}
