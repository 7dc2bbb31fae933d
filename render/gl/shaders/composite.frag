// The CPU reference's per-pixel rules, written for the GPU (cpu_compositor.cpp; core's
// blend_weights.cpp for w2).
#version 330 core
uniform sampler2D synth;
uniform sampler2D video;
uniform sampler2D eye_depth;  // 1 / z_eye of the model (0: none), the mesh pass's second target
uniform sampler2D seen;       // 1 / z_real of the model seen from the real camera (0: none)
uniform int model_depth;      // the model-depth video view (depth_warp.h)
uniform mat3 A;
uniform vec3 b;
uniform float seen_tolerance;
uniform ivec2 vp_origin;
uniform ivec2 vp_size;
uniform int video_on;
uniform mat3 H;
uniform vec3 inv_depth;
uniform float inv_near;
uniform vec2 video_size;
uniform int per_pixel;
uniform float w_video;
uniform int nearest;
uniform int style;  // 0 none, 1 frame, 2 desaturate, 3 checker
uniform float desat;
uniform float checker_step;
uniform float fade;
uniform int cell;
uniform int frame_w;
uniform int stale;  // video past its age bound: the frame is drawn in every style
uniform vec3 frame_rgb;
out vec4 colour;

float pixel_weight(float kappa, vec2 q) {
  if (kappa <= 0.0) return 1.0;
  float x = min(abs(1.0 - 2.0 * q.x / video_size.x), 1.0);
  float y = min(abs(1.0 - 2.0 * q.y / video_size.y), 1.0);
  float inner = 1.0 - kappa;
  float w;
  if (x <= inner && y <= inner) w = 1.0;
  else if (y <= inner) w = (1.0 - x) / kappa;
  else if (x <= inner) w = (1.0 - y) / kappa;
  else w = 1.0 - length(vec2(x - inner, y - inner)) / kappa;
  w = clamp(w, 0.0, 1.0);
  return (sin((w - 0.5) * 3.14159265358979) + 1.0) * 0.5;
}

void main() {
  ivec2 pix = ivec2(gl_FragCoord.xy);
  ivec2 e = pix - vp_origin;
  vec3 s = floor(texelFetch(synth, pix, 0).rgb * 255.0 + 0.5);
  if (style == 2) {
    float grey = 0.299 * s.r + 0.587 * s.g + 0.114 * s.b;
    s += desat * (vec3(grey) - s);
  } else if (style == 3) {
    float step = (((e.x / cell + e.y / cell) & 1) != 0) ? -checker_step : checker_step;
    s = clamp(s + step, 0.0, 255.0);
  }
  if (fade > 0.0) s += fade * (vec3(128.0) - s);
  float a = 0.0;
  vec3 v = vec3(0.0);
  if (video_on != 0) {
    vec3 p = vec3(vec2(e) + 0.5, 1.0);
    float iz_model = model_depth != 0 ? texelFetch(eye_depth, pix, 0).r : 0.0;
    bool on_model = iz_model > 0.0;
    float iz = on_model ? iz_model : dot(inv_depth, p);
    vec3 h = on_model ? A * p + b * iz : H * p;
    if (iz > 0.0 && iz <= inv_near && h.z > 0.0) {
      vec2 q = h.xy / h.z;
      bool inside = q.x >= 0.0 && q.y >= 0.0 && q.x <= video_size.x && q.y <= video_size.y;
      if (inside && on_model) {
        ivec2 t = min(ivec2(q), ivec2(video_size) - 1);
        inside = iz / h.z >= texelFetch(seen, t, 0).r * (1.0 - seen_tolerance);
      }
      if (inside) {
        float weight = w_video;
        if (per_pixel != 0) {
          float strength = min(1.0, 2.0 * w_video);
          weight = strength * pixel_weight(min(1.0, 2.0 * (1.0 - w_video)), q);
        }
        a = weight;
        if (a > 0.0) {
          if (nearest != 0) {
            ivec2 t = min(ivec2(q), ivec2(video_size) - 1);
            v = texelFetch(video, t, 0).rgb * 255.0;
          } else {
            v = texture(video, q / video_size).rgb * 255.0;
          }
        }
      }
    }
  }
  vec3 o = s + a * (v - s);
  if ((style == 1 || (stale != 0 && style != 0)) && frame_w > 0 &&
      (e.x < frame_w || e.y < frame_w || e.x >= vp_size.x - frame_w || e.y >= vp_size.y - frame_w)) {
    o = frame_rgb;
  }
  colour = vec4(floor(clamp(o, 0.0, 255.0) + 0.5) / 255.0, 1.0);
}
