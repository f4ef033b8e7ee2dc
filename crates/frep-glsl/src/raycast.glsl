// ---- ray caster -----------------------------------------------------------
// Per pixel: clip the ray to the box [u_box_min, u_box_max]; interval
// bisection along it (field_iv over the bounding box of a segment: strictly
// negative = outside, discarded; entirely >= 0 = inside, hit at its start;
// otherwise split, nearest half first, down to the pixel footprint), then
// point samples and bisection on the sign of field() in the first
// undecided pixel-sized segment that has an inside sample. f >= 0 is inside.
uniform vec2 u_resolution;
uniform mat4 u_inv_view_proj;
uniform vec3 u_box_min;
uniform vec3 u_box_max;
uniform int u_max_steps;
uniform vec3 u_background;
out vec4 frag_color;

const int HF_STACK = 32;
const int HF_BISECT = 12;

void hf_ray(vec2 frag, out vec3 o, out vec3 d) {
  vec2 ndc = frag / u_resolution * 2.0 - 1.0;
  vec4 a = u_inv_view_proj * vec4(ndc, -1.0, 1.0);
  vec4 b = u_inv_view_proj * vec4(ndc, 0.0, 1.0);
  o = a.xyz / a.w;
  d = normalize(b.xyz / b.w - o);
}

vec2 hf_segment_iv(vec3 o, vec3 d, vec2 seg) {
  vec3 pa = o + d * seg.x;
  vec3 pb = o + d * seg.y;
  vec3 lo = min(pa, pb);
  vec3 hi = max(pa, pb);
  return field_iv(vec2(lo.x, hi.x), vec2(lo.y, hi.y), vec2(lo.z, hi.z));
}

// Linear RGB to the (approximately sRGB) output.
vec4 hf_output(vec3 c) { return vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0); }

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
  vec3 dd = d;
  if (abs(dd.x) < 1e-20) dd.x = 1e-20;
  if (abs(dd.y) < 1e-20) dd.y = 1e-20;
  if (abs(dd.z) < 1e-20) dd.z = 1e-20;
  vec3 inv = 1.0 / dd;
  vec3 ta3 = (u_box_min - o) * inv;
  vec3 tb3 = (u_box_max - o) * inv;
  vec3 tmin = min(ta3, tb3);
  vec3 tmax = max(ta3, tb3);
  float t0 = max(max(tmin.x, tmin.y), max(tmin.z, 0.0));
  float t1 = min(min(tmax.x, tmax.y), tmax.z);
  if (!(t0 < t1)) {
    frag_color = hf_output(u_background);
    return;
  }
  vec2 stack[HF_STACK];
  int sp = 1;
  stack[0] = vec2(t0, t1);
  int steps = 0;
  bool capped = false;
  bool found = false;
  float hit = 0.0;
  while (sp > 0) {
    if (steps >= u_max_steps) { capped = true; break; }
    steps++;
    sp--;
    vec2 seg = stack[sp];
    vec2 f = hf_segment_iv(o, d, seg);
    if (f.y < 0.0) continue;
    if (f.x >= 0.0) { found = true; hit = seg.x; break; }
    if (seg.y - seg.x > fp0 + fp1 * seg.y && sp + 2 <= HF_STACK) {
      float m = 0.5 * (seg.x + seg.y);
      stack[sp] = vec2(m, seg.y);
      stack[sp + 1] = vec2(seg.x, m);
      sp += 2;
      continue;
    }
    // Pixel-sized and undecided: samples at the start, middle and end, then
    // bisection between the last outside and the first inside sample (one
    // call site of field()).
    float lo = seg.x;
    float hi = seg.y;
    bool inside = false;
    float h = 0.5 * (seg.y - seg.x);
    for (int j = 0; j < 3 + HF_BISECT; j++) {
      float t;
      if (!inside) {
        if (j >= 3) break;
        t = seg.x + float(j) * h;
      } else {
        t = 0.5 * (lo + hi);
      }
      if (field(o + d * t) >= 0.0) {
        inside = true;
        hi = t;
        if (j == 0) break;
      } else {
        lo = t;
      }
    }
    if (inside) { found = true; hit = hi; break; }
  }
  if (capped) {
    frag_color = vec4(1.0, 0.0, 1.0, 1.0);
    return;
  }
  if (!found) {
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
