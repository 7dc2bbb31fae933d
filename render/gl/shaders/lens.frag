// The lens pass per fragment: the eyes picture sampled at each channel's own point (green from
// the mesh, or from the exact lens polynomial; red and blue scaled from it about the centre).
#version 330 core
uniform sampler2D eyes;
uniform vec2 eyes_size;
uniform vec2 centre[2];
uniform vec2 lens_px[2];
uniform vec2 inv_unit_px;
uniform float max_radius;
uniform vec3 scale;
uniform float eye_w;
uniform int exact;
uniform float k[12];
uniform int k_count;
in vec2 green;
flat in int eye_i;
out vec4 colour;
void main() {
  vec2 q = gl_FragCoord.xy - lens_px[eye_i];
  vec2 d = q * inv_unit_px;
  float r = length(d);
  if (max_radius > 0.0 && r > max_radius) {
    colour = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  vec2 g = green;
  if (exact != 0) {
    // The lens polynomial at this fragment: green = centre + P(r) / (r P'(0)) * q.
    float p = 0.0;
    for (int i = k_count - 1; i >= 1; --i) p = p * r + k[i];
    g = centre[eye_i] + (r > 0.0 ? p : k[1]) / k[1] * q;
  }
  float lo = float(eye_i) * eye_w + 0.5;
  float hi = lo + eye_w - 1.0;
  vec2 c = centre[eye_i];
  vec3 rgb;
  for (int ch = 0; ch < 3; ++ch) {
    vec2 s = c + scale[ch] * (g - c);
    s.x = clamp(s.x, lo, hi);
    rgb[ch] = texture(eyes, s / eyes_size)[ch];
  }
  colour = vec4(rgb, 1.0);
}
