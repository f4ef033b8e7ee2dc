// ---- the standalone ray caster's main -------------------------------------
// After standalone_scene.glsl and trace.glsl: the ray of u_inv_view_proj
// clipped to the box, traced, shaded with a key and a fill light over
// hf_material's colour.
void main() {
  vec3 o;
  vec3 d;
  hf_ray(gl_FragCoord.xy, o, d);
  vec3 o1;
  vec3 d1;
  hf_ray(gl_FragCoord.xy + vec2(1.0, 0.0), o1, d1);
  // Pixel footprint at distance t: fp0 + fp1 * t.
  float fp0 = length(o1 - o);
  float fp1 = length(d1 - d);
  float t0;
  float t1;
  hf_box_span(o, d, u_box_min, u_box_max, t0, t1);
  if (!(t0 < t1)) {
    frag_color = hf_output(u_background);
    return;
  }
  float hit;
  int traced = hf_trace(o, d, t0, t1, fp0, fp1, hit);
  if (traced == HF_CAPPED) {
    frag_color = vec4(1.0, 0.0, 1.0, 1.0);
    return;
  }
  if (traced == HF_MISS) {
    frag_color = hf_output(u_background);
    return;
  }
  vec3 p = o + d * hit;
  vec4 g = field_grad(p);
  // f >= 0 inside: the gradient points inward.
  vec3 n = -g.yzw;
  float ln = length(n);
  n = (ln > 0.0 && !isinf(ln) && !isnan(ln)) ? n / ln : -d;
  if (dot(n, d) > 0.0) n = -n;
  vec3 base = hf_material(p);
  vec3 key = normalize(vec3(0.6, 0.8, 0.5));
  vec3 fill = -d;
  float diff = max(dot(n, key), 0.0);
  float spec = pow(max(dot(reflect(-key, n), -d), 0.0), 32.0);
  vec3 c = base * (0.15 + 0.65 * diff + 0.3 * max(dot(n, fill), 0.0)) + vec3(0.25 * spec);
  frag_color = hf_output(c);
}
