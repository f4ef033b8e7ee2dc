// Generated from crates/frep-glsl by `FREP_BLESS=1 cargo test -p frep-glsl`.
// Do not edit: change crates/frep-glsl/src/scene.glsl instead.

/** The viewer's scene (GLSL, no `#version`): frep-glsl's `SCENE`. */
export const SCENE_GLSL = `
// ---- the ray's span in a box -----------------------------------------------
// Slab test: [t0, t1] of o + t d inside [lo, hi], from t = 0 on (empty when
// t0 >= t1). Axis-parallel rays get a tiny direction instead of a zero.
void hf_box_span(vec3 o, vec3 d, vec3 lo, vec3 hi, out float t0, out float t1) {
  vec3 dd = d;
  if (abs(dd.x) < 1e-20) dd.x = 1e-20;
  if (abs(dd.y) < 1e-20) dd.y = 1e-20;
  if (abs(dd.z) < 1e-20) dd.z = 1e-20;
  vec3 inv = 1.0 / dd;
  vec3 ta3 = (lo - o) * inv;
  vec3 tb3 = (hi - o) * inv;
  vec3 tmin = min(ta3, tb3);
  vec3 tmax = max(ta3, tb3);
  t0 = max(max(tmin.x, tmin.y), max(tmin.z, 0.0));
  t1 = min(min(tmax.x, tmax.y), tmax.z);
}
// ---- the viewer's scene --------------------------------------------------
// What every client-drawn mode of the studio shares (the generated ray
// caster and the volume): the camera, scene and section uniforms, sRGB
// conversions, the background gradient, the ray of a pixel (frep-render's
// ray_at), the section clip and the lighting (frep-render's Lighting,
// without ambient occlusion). The studio fills the uniforms from its own
// camera and scene (web/src/viewer/modes/raycast-scene.ts).
uniform vec2 u_resolution;
uniform vec3 u_eye;
uniform vec3 u_right;
uniform vec3 u_up;
uniform vec3 u_forward;
uniform float u_k;
uniform float u_perspective;
uniform vec3 u_box_min;
uniform vec3 u_box_max;
uniform int u_max_steps;
uniform vec3 u_bg_top;
uniform vec3 u_bg_bottom;
uniform vec3 u_base;
uniform vec3 u_cap;
uniform vec3 u_key;
uniform vec3 u_fill;
uniform vec3 u_rim;
uniform vec3 u_key_color;
uniform vec3 u_fill_color;
uniform vec3 u_rim_color;
uniform vec3 u_sky;
uniform vec3 u_ground;
uniform float u_specular;
uniform float u_shininess;
uniform vec4 u_section;
uniform float u_section_on;
out vec4 frag_color;

float hf_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? c * 12.92 : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}
float hf_linear(float c) {
  return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}
vec4 hf_background() {
  float h = u_resolution.y;
  float row = h - 1.0 - floor(gl_FragCoord.y);
  float s = h > 1.0 ? row / (h - 1.0) : 0.5;
  return vec4(mix(u_bg_top, u_bg_bottom, s), 1.0);
}
bool hf_persp() { return u_perspective > 0.5; }
// frep-render's RayMaker::ray_at: the shorter side spans [-k, k].
void hf_pixel_ray(out vec3 o, out vec3 d) {
  float s = 0.5 * min(u_resolution.x, u_resolution.y);
  vec2 uv = (gl_FragCoord.xy - 0.5 * u_resolution) / s;
  vec3 side = (u_right * uv.x + u_up * uv.y) * u_k;
  o = hf_persp() ? u_eye : u_eye + side;
  d = hf_persp() ? normalize(u_forward + side) : u_forward;
}
// The pixel's footprint at distance t is fp.x + fp.y * t.
vec2 hf_footprint() {
  float s = 0.5 * min(u_resolution.x, u_resolution.y);
  return hf_persp() ? vec2(0.0, u_k / s) : vec2(u_k / s, 0.0);
}
// The ray's span inside the box and on the kept side of the section;
// cap_t is where it enters through the section plane (else -1e30).
void hf_clip(vec3 o, vec3 d, out float t0, out float t1, out float cap_t) {
  hf_box_span(o, d, u_box_min, u_box_max, t0, t1);
  cap_t = -1e30;
  if (u_section_on > 0.5) {
    float dn = dot(u_section.xyz, d);
    float num = u_section.w - dot(u_section.xyz, o);
    if (abs(dn) < 1e-12) {
      if (num < 0.0) t1 = t0 - 1.0;
    } else if (dn > 0.0) {
      t1 = min(t1, num / dn);
    } else if (num / dn > t0) {
      t0 = num / dn;
      cap_t = t0;
    }
  }
}
bool hf_on_cap(float hit, float cap_t) {
  return cap_t > -1e29 && hit <= cap_t + 1e-6 * max(1.0, abs(cap_t));
}
// Shades a hit: raw normal g (any length; flipped towards the viewer),
// albedo in sRGB; returns the output colour.
vec4 hf_shade(vec3 p, vec3 g, vec3 albedo_srgb) {
  vec3 v = hf_persp() ? normalize(u_eye - p) : -u_forward;
  float ln = length(g);
  vec3 n = (ln > 0.0 && !isinf(ln) && !isnan(ln)) ? g / ln : v;
  if (dot(n, v) < 0.0) n = -n;
  vec3 albedo = vec3(hf_linear(albedo_srgb.r), hf_linear(albedo_srgb.g), hf_linear(albedo_srgb.b));
  float hemi = 0.5 + 0.5 * n.z;
  float kd = max(dot(n, u_key), 0.0);
  float fd = max(dot(n, u_fill), 0.0);
  float rd = max(dot(n, u_rim), 0.0);
  vec3 half_v = normalize(u_key + v);
  float spec = kd > 0.0 ? u_specular * pow(max(dot(n, half_v), 0.0), u_shininess) : 0.0;
  vec3 amb = u_sky * hemi + u_ground * (1.0 - hemi);
  vec3 diffuse = u_key_color * kd + u_fill_color * fd + u_rim_color * rd;
  vec3 lin = albedo * (amb + diffuse) + spec * u_key_color;
  return vec4(hf_srgb(lin.r), hf_srgb(lin.g), hf_srgb(lin.b), 1.0);
}
`;

/** The uniforms `SCENE_GLSL` declares (frep-glsl's `SCENE_UNIFORMS`). */
export const SCENE_UNIFORMS = [
  'u_resolution',
  'u_eye',
  'u_right',
  'u_up',
  'u_forward',
  'u_k',
  'u_perspective',
  'u_box_min',
  'u_box_max',
  'u_max_steps',
  'u_bg_top',
  'u_bg_bottom',
  'u_base',
  'u_cap',
  'u_key',
  'u_fill',
  'u_rim',
  'u_key_color',
  'u_fill_color',
  'u_rim_color',
  'u_sky',
  'u_ground',
  'u_specular',
  'u_shininess',
  'u_section',
  'u_section_on',
] as const;

/** The vertex shader: one full-screen triangle (frep-glsl's `vertex_shader`). */
export const VERTEX_SHADER = `#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
`;
