// ---- the studio's ray caster -----------------------------------------------
// Mode 4a: the viewer's camera, section plane, background and lighting
// (scene.glsl), traced by hf_trace, so that the picture matches the
// server's images. HF_ATTRS is 1 when the model has colours (`attrs`).
void main() {
  vec3 o;
  vec3 d;
  hf_pixel_ray(o, d);
  vec2 fp = hf_footprint();
  float t0;
  float t1;
  float cap_t;
  hf_clip(o, d, t0, t1, cap_t);
  if (!(t0 < t1)) {
    frag_color = hf_background();
    return;
  }
  float hit;
  int traced = hf_trace(o, d, t0, t1, fp.x, fp.y, hit);
  if (traced == HF_CAPPED) {
    frag_color = vec4(1.0, 0.0, 1.0, 1.0);
    return;
  }
  if (traced == HF_MISS) {
    frag_color = hf_background();
    return;
  }
  vec3 p = o + d * hit;
  bool on_cap = hf_on_cap(hit, cap_t);
  vec4 g = field_grad(p);
  // f >= 0 inside: the gradient points inward; on the cut face, the plane's normal.
  vec3 n = on_cap ? u_section.xyz : -g.yzw;
#if HF_ATTRS
  vec3 c = attrs(p);
  vec3 albedo = any(isnan(c)) ? (on_cap ? u_cap : u_base) : clamp(c, 0.0, 1.0);
#else
  vec3 albedo = on_cap ? u_cap : u_base;
#endif
  frag_color = hf_shade(p, n, albedo);
}
