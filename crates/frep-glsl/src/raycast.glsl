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

// Deepest subdivision of the ray (segments of 2^-HF_LEVELS of its length)
// and bisection steps on the point sign.
const int HF_LEVELS = 22;
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
  // One loop, bounded by a uniform, with exactly one call site of field_iv
  // and one of field (SwiftShader inlines every call site and unrolls loops
  // of constant bounds; a stack array indexed dynamically is slow there).
  // The segments form an implicit binary tree over [t0, t1]: segment `idx`
  // of level `lvl` is [t0 + idx len, t0 + (idx + 1) len], len = (t1 - t0) /
  // 2^lvl; the next segment in ray order is idx + 1 with its trailing zero
  // bits dropped (back up the tree), so no stack is needed.
  // mode 0: interval test of the segment; mode 1: point samples at its
  // start, middle and end; mode 2: bisection between lo (outside) and hi.
  int lvl = 0;
  int idx = 0;
  int mode = 0;
  int j = 0;
  int steps = 0;
  bool capped = false;
  bool found = false;
  float hit = 0.0;
  float lo = t0;
  float hi = t1;
  vec2 seg = vec2(t0, t1);
  int iters = u_max_steps * (4 + HF_BISECT);
  for (int it = 0; it < iters; it++) {
    bool next = false;
    if (mode == 0) {
      if (steps >= u_max_steps) { capped = true; break; }
      steps++;
      vec2 f = hf_segment_iv(o, d, seg);
      if (f.y < 0.0) {
        next = true;
      } else if (f.x >= 0.0) {
        found = true;
        hit = seg.x;
        break;
      } else if (seg.y - seg.x > fp0 + fp1 * seg.y && lvl < HF_LEVELS) {
        lvl++;
        idx *= 2;
      } else {
        // Pixel-sized and undecided: point samples.
        mode = 1;
        j = 0;
        lo = seg.x;
        hi = seg.y;
      }
    } else {
      float t = mode == 1 ? seg.x + float(j) * 0.5 * (seg.y - seg.x) : 0.5 * (lo + hi);
      bool inside = field(o + d * t) >= 0.0;
      if (mode == 1) {
        if (inside && j == 0) { found = true; hit = t; break; }
        if (inside) {
          hi = t;
          mode = 2;
          j = 0;
        } else {
          lo = t;
          j++;
          if (j == 3) { mode = 0; next = true; }
        }
      } else {
        if (inside) hi = t; else lo = t;
        j++;
        if (j == HF_BISECT) { found = true; hit = hi; break; }
      }
    }
    if (next) {
      idx++;
      // Drop the trailing zero bits of idx: back up to the parent level.
      int tz = int(round(log2(float(idx & -idx))));
      idx = idx >> tz;
      lvl -= tz;
      if (lvl <= 0) break;
    }
    float len = (t1 - t0) / float(1 << lvl);
    seg = vec2(t0 + float(idx) * len, t0 + float(idx + 1) * len);
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
