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
