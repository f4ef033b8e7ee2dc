/**
 * The volume mode's fragment shader: the server's 8-bit 3D texture of the
 * field (`128 + 127 f / scale`, 128 the surface, x fastest; voxel centres
 * at texel centres) ray marched in steps of a fraction of a voxel, the
 * crossing refined by bisection on the trilinear value, the normal from
 * central differences. The section plane shows the inside: the cut face
 * is coloured by the attributes `s[]` when a colour volume is given
 * (sampled by the WebAssembly kernel), else by the section colour. Camera,
 * background and lighting are mode 4a's (SCENE_GLSL, generated from frep-glsl).
 */
import { SCENE_GLSL } from './scene-glsl';

export const VOLUME_FRAGMENT = `#version 300 es
precision highp float;
precision highp int;
precision highp sampler3D;
uniform sampler3D u_volume;
uniform sampler3D u_colors;
uniform float u_has_colors;
uniform vec3 u_dims;
uniform float u_step;
${SCENE_GLSL}
const int HF_BISECT = 8;

vec3 hf_uvw(vec3 p) { return (p - u_box_min) / (u_box_max - u_box_min); }
// >= 0 inside (bytes >= 128); failed samples (byte 0) read as outside.
float hf_vol(vec3 p) { return texture(u_volume, hf_uvw(p)).r * 255.0 - 128.0; }

void main() {
  vec3 o;
  vec3 d;
  hf_pixel_ray(o, d);
  float t0;
  float t1;
  float cap_t;
  hf_clip(o, d, t0, t1, cap_t);
  if (!(t0 < t1)) {
    frag_color = hf_background();
    return;
  }
  vec3 voxel = (u_box_max - u_box_min) / u_dims;
  float dt = u_step * min(voxel.x, min(voxel.y, voxel.z));
  bool found = false;
  float hit = t0;
  float prev = t0;
  for (int i = 0; i < u_max_steps; i++) {
    float t = min(t0 + float(i) * dt, t1);
    if (hf_vol(o + d * t) >= 0.0) {
      found = true;
      hit = t;
      break;
    }
    prev = t;
    if (t >= t1) break;
  }
  if (!found) {
    frag_color = hf_background();
    return;
  }
  if (hit > t0) {
    float lo = prev;
    float hi = hit;
    for (int k = 0; k < HF_BISECT; k++) {
      float m = 0.5 * (lo + hi);
      if (hf_vol(o + d * m) >= 0.0) hi = m; else lo = m;
    }
    hit = hi;
  }
  vec3 p = o + d * hit;
  bool on_cap = hf_on_cap(hit, cap_t);
  vec3 h = 0.5 * voxel;
  vec3 g = vec3(
    hf_vol(p + vec3(h.x, 0.0, 0.0)) - hf_vol(p - vec3(h.x, 0.0, 0.0)),
    hf_vol(p + vec3(0.0, h.y, 0.0)) - hf_vol(p - vec3(0.0, h.y, 0.0)),
    hf_vol(p + vec3(0.0, 0.0, h.z)) - hf_vol(p - vec3(0.0, 0.0, h.z))) / (2.0 * h);
  // f >= 0 inside: the gradient points inward; on the cut face, the plane's normal.
  vec3 n = on_cap ? u_section.xyz : -g;
  vec4 c = texture(u_colors, hf_uvw(p));
  vec3 albedo = (u_has_colors > 0.5 && c.a > 0.5) ? c.rgb : (on_cap ? u_cap : u_base);
  frag_color = hf_shade(p, n, albedo);
}
`;
